/* entries.h -- the entries of the renderer table (private): one per file of renderers/src. */
#ifndef RENDERERS_ENTRIES_H
#define RENDERERS_ENTRIES_H

#include "light/illuminance.h"
#include "renderers/renderer.h"

/** The exact (Whitted) reference renderer (exact.c). */
extern const rn_renderer_t rn_exact_entry;
/** The pencil renderer of the 1987 paper's section 4.1 (pencil.c). */
extern const rn_renderer_t rn_pencil_entry;
/** Beam tracing of polyhedra, 1987 paper section 4.1 (3) (beam.c). */
extern const rn_renderer_t rn_beam_entry;

/** The caustic maps plan asks for (RT_EFFECT_CAUSTICS), by `method` unless c names another: *run
 *  becomes plan pointing at *maps (released with rt_caustic_maps_free()); without the effect *run
 *  is plan and nothing is made. What the maps took goes to *out (may be NULL), and on failure the
 *  reason to out->why. */
rt_status_t rn__caustics_make(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                              lt_method_t method, rt_plan_t *run, rt_caustic_maps_t *maps,
                              rn_caustic_stats_t *out);

#endif
