/* pov.h -- a scene written as a POV-Ray 3.7 scene file: the peer renderer beside the exact one
 * (issue 26, "a peer beside the exact renderer"; docs/pencil.md, "POV-Ray as a peer").
 *
 * The file holds the same camera (every pixel centre's ray, exactly), objects, materials, lights,
 * background and ray depth as the scene, so that POV-Ray traces the same ray trees as the exact
 * renderer. What cannot be written so is refused with a message naming it, never dropped; what
 * is written but shades differently in POV-Ray (its shadows through glass, its total internal
 * reflection) is listed as notes, in the file and to the caller.
 *
 * A "flat" file is the export check's: every object a flat colour that encodes its index (and, on
 * a checkerboard, the square's parity), no lights, no secondary rays, a black background, so that
 * a 1-spp POV-Ray render can be compared pixel by pixel with the exact renderer's id channel.
 *
 * Functions return 0 on success, or -1 with a one-line reason in err[cap]. */
#ifndef IO_POV_H
#define IO_POV_H

#include <stddef.h>
#include <stdio.h>

#include "core/scene.h"

/** What to write. */
typedef struct {
  int flat;           /**< 1: the export check's flat file (above); 0: the scene as shaded */
  int spp;            /**< samples per pixel the file is for, s x s (1, 4, 9, ...): POV-Ray
                           renders it at s times the camera's width and height without
                           anti-aliasing, and s x s blocks of its pixels averaged are the
                           exact renderer's pixels (the header says so) */
  const char *source; /**< the scene's name for the header ("scenes/x.json"), or NULL */
} io_pov_options_t;

#define IO_POV_OPTIONS_DEFAULT                                                                     \
  { 0, 1, NULL }

/** The flat file's colour code of a pixel: 0 for the background, object + 1 for object `object`
 *  (index into rt_scene_t.object), plus IO_POV_ODD on the odd squares of a checkerboard (the
 *  squares whose material is material2). Written as pigment rgb <R, G, B> / 255 with
 *  R = code & 255, G = (code >> 8) & 255, B = code >> 16: rendered with File_Gamma=1.0 into an
 *  8-bit PNG the three bytes come back exactly, and the code is R + 256 G + 65536 B. */
#define IO_POV_ODD (1u << 23)

/** The most objects a flat file can encode. */
#define IO_POV_FLAT_MAX_OBJECTS ((int)IO_POV_ODD - 2)

/** Whether scene s (prepared: its camera valid) can be written: -1 naming the first object,
 *  material, light or setting that cannot be mapped (a flat file needs only the camera and the
 *  geometry), else 0 with the differences POV-Ray will still show in notes[ncap] (may be NULL),
 *  one line each, "" when none. */
int io_pov_check(const rt_scene_t *s, const io_pov_options_t *o, char *notes, size_t ncap,
                 char *err, size_t cap);

/** Write scene s as a POV-Ray 3.7 scene to f, after io_pov_check() (notes as there; they are
 *  comments in the file too). The header comments name the pencil version and command line
 *  (output.h's provenance) and the POV-Ray command line that renders the file. */
int io_pov_write(FILE *f, const rt_scene_t *s, const io_pov_options_t *o, char *notes, size_t ncap,
                 char *err, size_t cap);

/** io_pov_write() into the file at path, replaced atomically (output.h); nothing is written when
 *  the scene is refused (err then holds io_pov_check()'s reason, without the path). */
int io_pov_export(const char *path, const rt_scene_t *s, const io_pov_options_t *o, char *notes,
                  size_t ncap, char *err, size_t cap);

#endif
