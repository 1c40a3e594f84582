/* caustics.c -- the caustic maps a render makes before it traces, shared by the entries: each
 * entry names its own default method (the exact renderer's maps by backward ray tracing, the
 * pencil renderer's by grid-pencils), and shading reads the maps through its copy of the plan
 * (core/caustics.h). */
#include <stdio.h>
#include <string.h>

#include "entries.h"

/* The maps' options: the common options', else the entry's default method and the defaults. */
static lt_caustic_options_t options(const rn_common_t *c, lt_method_t method) {
  if (c->caustic_method)
    method = (lt_method_t)(c->caustic_method - 1);
  lt_caustic_options_t o = {method,
                            c->caustic_rays               ? c->caustic_rays
                            : method == LT_METHOD_PHOTONS ? RN_CAUSTIC_PHOTON_RAYS
                                                          : RN_CAUSTIC_PENCIL_RAYS,
                            c->caustic_cells ? c->caustic_cells : RN_CAUSTIC_CELLS,
                            c->threads,
                            NULL,
                            NULL,
                            LT_AREA_FILTER_NONE}; /* the filter's cost: docs/renderer.md */
  return o;
}

size_t rn_caustic_bytes(const rn_renderer_t *r, const rt_scene_t *s, const rt_plan_t *plan,
                        const rn_common_t *c) {
  if (!rt_plan_has(plan, RT_EFFECT_CAUSTICS))
    return 0;
  /* the entries' defaults, as exact.c and pencil.c pass them to rn__caustics_make() */
  lt_method_t method = strcmp(r->name, "exact") == 0 ? LT_METHOD_PHOTONS : LT_METHOD_GRID_PENCIL;
  lt_caustic_options_t o = options(c, method);
  return lt_caustic_bytes(s, &plan->caustic, &o);
}

rt_status_t rn__caustics_make(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                              lt_method_t method, rt_plan_t *run, rt_caustic_maps_t *maps,
                              rn_caustic_stats_t *out) {
  rn_caustic_stats_t local = {0};
  rn_caustic_stats_t *cs = out ? out : &local;
  memset(cs, 0, sizeof *cs);
  memset(maps, 0, sizeof *maps);
  *run = *plan;
  run->maps = NULL;
  if (!rt_plan_has(plan, RT_EFFECT_CAUSTICS))
    return RT_OK;
  lt_caustic_options_t o = options(c, method);
  method = o.method;
  lt_caustic_stats_t st;
  rt_status_t r = lt_caustic_maps(s, &plan->caustic, &o, maps, &st, cs->why, sizeof cs->why);
  cs->method = lt_method_name(method);
  cs->rays = method == LT_METHOD_POLYGONS ? 0 : o.side;
  cs->cells = o.cells;
  if (r != RT_OK)
    return r;
  cs->maps = st.maps;
  cs->empty = st.empty;
  cs->traced = st.st.rays;
  cs->seconds = st.st.seconds;
  cs->outside = st.flux_outside;
  run->maps = maps;
  return RT_OK;
}
