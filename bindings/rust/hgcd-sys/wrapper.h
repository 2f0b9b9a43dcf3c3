/* What hgcd-sys binds: the public API and the reference scenes' support
 * library (libhgcd_scene), which the safe crate's `scene` module wraps. */
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>
