/* povray.h -- POV-Ray 3.7 timed as a peer of the exact renderer (issue 26, "a peer beside the
 * exact renderer"; docs/pencil.md, "POV-Ray as a peer"): the scene exported by io/pov.h into a
 * private directory and rendered by the povray program at s times the image's size without
 * anti-aliasing for s x s samples per pixel (so that its pixel centres are the exact renderer's
 * sample grid), with no output file, its times and ray counts read from its statistics.
 *
 * POV-Ray reads no user configuration: its HOME is the private directory, which holds an empty
 * .povray/3.7/povray.conf and an empty povray.ini named by POVINI; nothing else of this process's
 * environment reaches it (no DISPLAY). The system's /etc/povray/3.7/povray.conf (its I/O
 * restrictions) still applies; the render writes no file. */
#ifndef VALIDATION_POVRAY_H
#define VALIDATION_POVRAY_H

#include <stddef.h>
#include <stdint.h>

#include "core/scene.h"

/** A POV-Ray installation and its private directory. */
typedef struct {
  char exe[4096];   /**< the povray program found on PATH (absolute path) */
  char dir[4096];   /**< the private directory ("" when none): HOME, povray.ini, .pov, logs */
  char version[64]; /**< the version of its last render's banner ("3.7.0.10.unofficial"), or
                         "" before one */
} val_povray_t;

/** The figures of one POV-Ray render. */
typedef struct {
  double trace_s;        /**< "Trace Time ... CPU-seconds total" of its statistics: the CPU time
                              of its render threads, parsing, bounding, start-up and the image's
                              assembly excluded (printed to the millisecond) */
  double process_s;      /**< user + system CPU seconds of the whole povray process (wait4) */
  uint64_t rays;         /**< "Rays": camera, reflected, refracted and transmitted rays as
                              POV-Ray counts them (one call of its tracer each: rays at the
                              depth limit count, though they return at once) */
  uint64_t shadow_tests; /**< "Shadow Ray Tests": a shadow ray counts once per search along it
                              (three through a glass sphere: in, out, clear) */
} val_povray_run_t;

/** Find povray on PATH and make the private directory (under TMPDIR, else /tmp). 0; 1 when
 *  povray is not installed (why in err, naming scripts/deps); -1 when the directory cannot be
 *  made (why in err). */
int val_povray_open(val_povray_t *p, char *err, size_t cap);

/** Remove the private directory and what it holds; safe on a closed or failed one. */
void val_povray_close(val_povray_t *p);

/** Export scene s (io_pov_export(), shaded) for spp = side^2 samples per pixel into the private
 *  directory as scene-SPP.pov; `source` names the scene in its header. 0, or -1 with the
 *  exporter's reason (a refused scene) or the file's in err. */
int val_povray_export(val_povray_t *p, const rt_scene_t *s, int spp, const char *source, char *err,
                      size_t cap);

/** Render scene-SPP.pov (val_povray_export()) at side times s's width and height, -A (no
 *  anti-aliasing), +WT`threads`, -F (no file), -D (no display); its figures into *out, its
 *  output to scene-SPP.log. 0, or -1 when it failed or its statistics lack a figure (why in err,
 *  naming the log). */
int val_povray_render(val_povray_t *p, const rt_scene_t *s, int spp, int threads,
                      val_povray_run_t *out, char *err, size_t cap);

/** POV-Ray as the peer of timed runs (val_peer_t of validation/figures.h, with
 *  val_povray_peer_run()): the scene exported for the spp first (val_povray_export()). */
typedef struct {
  val_povray_t *pv;      /**< the installation and its private directory */
  const rt_scene_t *s;   /**< the scene (its size) */
  int threads;           /**< POV-Ray's render threads (+WT) */
  const char *who;       /**< the command, for messages ("pencil bench pencil") */
  int n;                 /**< runs so far */
  double process[101];   /**< each run's process CPU seconds (the first 101) */
  val_povray_run_t last; /**< the last run's figures */
} val_povray_peer_t;

/** val_peer_t.run: one val_povray_render() of ctx (a val_povray_peer_t); its Trace Time CPU
 *  seconds and its own ray count (Rays + Shadow Ray Tests). 0, or -1 after a message on stderr
 *  naming the command and the log. */
int val_povray_peer_run(void *ctx, int spp, double *seconds, uint64_t *rays);

/** Parse POV-Ray's console output `log` (NUL-terminated) into *out (process_s untouched) and
 *  the banner's version into version[vcap]. 0, or -1 naming the first figure missing. */
int val_povray_parse(const char *log, val_povray_run_t *out, char *version, size_t vcap, char *err,
                     size_t cap);

#endif
