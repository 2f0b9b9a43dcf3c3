/* hgcd version: the single source of the version number.
 * The Makefile and meson.build both read these three lines. */
#ifndef HGCD_VERSION_H
#define HGCD_VERSION_H

#define HGCD_VERSION_MAJOR 0
#define HGCD_VERSION_MINOR 1
#define HGCD_VERSION_PATCH 0

#endif
