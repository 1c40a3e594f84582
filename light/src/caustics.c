/* caustics.c -- a render's caustic maps (issue 25): for each receiver plane of the effects plan
 * and each mapped light, the illuminance map of the light that reaches the plane after at least
 * one reflection or refraction (core/caustics.h says how shading uses them). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/image.h"
#include "internal.h"

/* W x H with `cells` along the longer side of extent ext, the other in proportion (at least 1). */
static void map_size(const double ext[4], int cells, int *w, int *h) {
  double a = ext[1] - ext[0], b = ext[3] - ext[2];
  if (a >= b) {
    *w = cells;
    *h = (int)fmax(1.0, fmin((double)cells, round(cells * b / a)));
  } else {
    *h = cells;
    *w = (int)fmax(1.0, fmin((double)cells, round(cells * a / b)));
  }
}

static double wall(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Rays a side of each mesh point's grid for an area light of mesh N: a point light's shared among
 * the N x N points (at least 33 for grid-pencils, whose pencils divide where they must, 17 for
 * photons; never more than the point light's). */
static int point_side(const lt_caustic_options_t *o, int mesh) {
  int side = (o->side + mesh - 1) / mesh, least = o->method == LT_METHOD_GRID_PENCIL ? 33 : 17;
  return side < least ? (o->side < least ? o->side : least) : side;
}

static int mesh_of(const rt_light_t *L) {
  return L->kind != RT_LIGHT_AREA ? 1 : L->samples > 0 ? L->samples : RT_AREA_SAMPLES_DEFAULT;
}

size_t lt_caustic_bytes(const rt_scene_t *s, const rt_caustic_plan_t *cp,
                        const lt_caustic_options_t *o) {
  int nmaps = cp->nplane * __builtin_popcount(cp->lights);
  if (nmaps == 0)
    return 0;
  double cells = 3.0 * (double)o->cells * (double)o->cells * sizeof(double); /* at most square */
  double grid = 0.0; /* grid-pencils' rays of one band of a grid face's rows */
  for (int l = 0; l < s->nlight && l < 32; l++)
    if (cp->lights & (1u << l) && o->method == LT_METHOD_GRID_PENCIL) {
      double side =
          s->light[l].kind == RT_LIGHT_AREA ? point_side(o, mesh_of(&s->light[l])) : o->side;
      grid = fmax(grid, fmin(side, LT_GRID_BAND + 1.0) * side * (double)sizeof(lt_arrivals_t));
    }
  double bytes = nmaps * cells + rt_thread_count(o->threads) * cells + grid;
  return bytes >= (double)SIZE_MAX ? SIZE_MAX : (size_t)bytes;
}

rt_status_t lt_caustic_maps(const rt_scene_t *s, const rt_caustic_plan_t *cp,
                            const lt_caustic_options_t *o, rt_caustic_maps_t *out,
                            lt_caustic_stats_t *st, char *why, size_t cap) {
  memset(out, 0, sizeof *out);
  memset(st, 0, sizeof *st);
  if (o->cells < 1 || o->cells > LT_MAX_GRID ||
      (o->method != LT_METHOD_POLYGONS && (o->side < 2 || o->side > LT_MAX_GRID))) {
    snprintf(why, cap, "caustic maps: %d cells or %d rays per side out of range", o->cells,
             o->side);
    return RT_EINVAL;
  }
  rt_status_t rs = lt_method_check(s, o->method, why, cap);
  if (rs != RT_OK)
    return rs;
  int nmaps = cp->nplane * __builtin_popcount(cp->lights);
  out->nobject = s->nobject;
  out->nlight = s->nlight;
  out->plane = malloc((size_t)(s->nobject > 0 ? s->nobject : 1) * sizeof *out->plane);
  out->index = malloc((size_t)(cp->nplane * s->nlight > 0 ? cp->nplane * s->nlight : 1) *
                      sizeof *out->index);
  out->map = calloc((size_t)(nmaps > 0 ? nmaps : 1), sizeof *out->map);
  if (!out->plane || !out->index || !out->map) {
    rt_caustic_maps_free(out);
    return RT_ENOMEM;
  }
  for (int k = 0; k < s->nobject; k++)
    out->plane[k] = -1;
  for (int k = 0; k < cp->nplane * s->nlight; k++)
    out->index[k] = -1;
  double t0 = wall(), reached = 0.0, outside = 0.0;
  rt_status_t status = RT_OK;
  for (int g = 0; g < cp->nplane && status == RT_OK; g++) {
    lt_receiver_t rc;
    double ext[4];
    status = lt_receiver_make(s, cp->object[g], cp->nobject[g], &rc, why, cap);
    if (status != RT_OK)
      break;
    if (!lt_default_extent(s, &rc, ext)) {
      st->unmapped++; /* a plane and nothing bounded to map around: it keeps the textbook shadow */
      continue;
    }
    for (int k = 0; k < cp->nobject[g]; k++)
      out->plane[cp->object[g][k]] = g;
    for (int l = 0; l < s->nlight && l < 32 && status == RT_OK; l++) {
      if (!(cp->lights & (1u << l)))
        continue;
      lt_light_extent(s, &rc, l, ext); /* each light's map covers its shadows */
      int w, h;
      map_size(ext, o->cells, &w, &h);
      lt_map_t m;
      status = lt_map_alloc(&m, w, h, ext[0], ext[1], ext[2], ext[3]);
      if (status != RT_OK)
        break;
      lt_options_t lo = LT_OPTIONS_DEFAULT;
      lo.method = o->method;
      lo.light = l;
      lo.side = o->side;
      lo.threads = o->threads;
      lo.indirect = 1;
      if (s->light[l].kind == RT_LIGHT_AREA) {
        /* the light's own mesh, as shading has it; the rays shared among its points, so that the
         * map costs about a point light's (photons: side / N a side each; grid-pencils, whose
         * pencils divide where they must, at least 33) */
        int mesh = mesh_of(&s->light[l]);
        lo.area_mesh = mesh;
        lo.area_filter = o->method == LT_METHOD_GRID_PENCIL ? o->area_filter : 0;
        lo.side = point_side(o, mesh);
        /* and the division depth too: a point carries 1 / N^2 of the light, so its pencils may
         * divide one level less for each fourfold share, log2(N) levels, but at least twice
         * (the glass of scenes/glass.json: 72 s at 6 levels, 4.4 s at 3) */
        int fewer = (int)lrint(log2((double)mesh));
        lo.max_split =
            lo.max_split - fewer < 2 ? (lo.max_split < 2 ? lo.max_split : 2) : lo.max_split - fewer;
      }
      lt_stats_t ls;
      status = lt_illuminance(s, &rc, &lo, &m, &ls);
      if (status != RT_OK) {
        snprintf(why, cap, "caustic maps: the %s map of light %d failed", lt_method_name(o->method),
                 l);
        lt_map_free(&m);
        break;
      }
      lt__stats_add(&st->st, &ls);
      reached += ls.flux_map + ls.flux_outside;
      outside += ls.flux_outside;
      rt_caustic_map_t *cm = &out->map[out->n];
      *cm = (rt_caustic_map_t){l,
                               g,
                               rc.p,
                               rc.u,
                               rc.v,
                               w,
                               h,
                               ext[0],
                               ext[2],
                               (ext[1] - ext[0]) / w,
                               (ext[3] - ext[2]) / h,
                               NULL,
                               0.0};
      for (size_t k = 0; k < 3 * (size_t)w * h; k++)
        cm->emax = fmax(cm->emax, m.e[k]);
      if (cm->emax > 0.0) {
        cm->e = m.e; /* the maps own it now */
        m.e = NULL;
      } else {
        st->empty++;
      }
      lt_map_free(&m);
      out->index[g * s->nlight + l] = out->n++;
      st->maps++;
      if (o->progress)
        o->progress(o->progress_ctx, st->maps, nmaps);
    }
  }
  if (status != RT_OK) {
    rt_caustic_maps_free(out);
    return status;
  }
  st->st.seconds = wall() - t0;
  /* a share, not below 0: where nothing falls beside the maps, the clipped deposits' rounding
   * (lt__deposit_*: the whole's flux less the cells') leaves the sum a few 1e-16 below it */
  st->flux_outside = reached > 0.0 ? fmax(0.0, outside / reached) : 0.0;
  return RT_OK;
}
