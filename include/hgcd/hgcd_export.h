/* Export macro: only hgcd_* symbols leave the shared library. */
#ifndef HGCD_EXPORT_H
#define HGCD_EXPORT_H

#if defined(_WIN32)
#  if defined(HGCD_BUILDING_LIBRARY)
#    define HGCD_API __declspec(dllexport)
#  else
#    define HGCD_API
#  endif
#elif defined(__GNUC__) || defined(__clang__)
#  define HGCD_API __attribute__((visibility("default")))
#else
#  define HGCD_API
#endif

#endif
