/* render_impl.h -- what beam tracing from the eye (render.c) and its dispersion image solids
 * (solids.c) share: a thread's state and the helpers the solids use. Private to beam/src. */
#ifndef BEAM_RENDER_IMPL_H
#define BEAM_RENDER_IMPL_H

#include <stdint.h>

#include "beam/beam.h"
#include "beam/render.h"
#include "core/shade.h"
#include "render/render.h"

/* Steps a beam's path and its prefix models can hold. */
#define BT_LEVELS (BM_MAX_STEPS + 1)
/* Linear pieces of a dispersion image solid along the wavelength axis: its points are traced
 * exactly at BT_SOLID_SEGS + 1 breakpoints (the range's ends, u_c where the beam tree's rays are,
 * and halfway between) and joined by chords; [P89] Eq. (15) is the one-piece tangent form. */
#define BT_SOLID_SEGS 4

/* The groups (an entry's path, face and refraction) known, in any tile, to have a subtree too
 * fine for solids: later entries of them skip recording (solids.c). Shared by the threads. */
typedef struct {
  struct sd_entry *ent; /* an entry of each */
  int n, cap;
} sd_fine_t;

/* One thread's state for a tile. */
typedef struct {
  const rt_scene_t *s;
  const rt_plan_t *plan;
  const bt_options_t *o;
  const bm_scene_t *b;
  bm_source_t src;
  double a0, b0;   /* parameters of the image's top-left corner */
  double cell;     /* parameter side of a sub-pixel cell */
  double pixel;    /* ... of a pixel (s cells) */
  int cx0, cy0;    /* the tile's first cell */
  int tcw, tch;    /* the tile's cells across and down */
  double *acc;     /* the tile's cells, RGB each (tcw * tch * 3) */
  double min_area; /* pieces of less parameter area are slivers */
  int *near;       /* scratch for bm_partition(), one list per level of recursion */
  int levels;      /* lists in near */
  xr_exact_t ex;
  rt_tracer_t tr;
  bt_stats_t st;
  /* the Fig. 10 measure (o->measure), per tile cell */
  xr_exact_t mex;  /* the measure's own exact tracer: the render's ray counts stay the render's */
  rt_tree_t probe; /* the exact tree of the cell centre being measured */
  int nodes;       /* nodes a tree may have (plan->tree_nodes) */
  double *err;     /* 3 a cell: the error, on the transmission-first path, strict */
  uint8_t *pts;    /* 1: a model's point on a measured surface; 2: traced exactly from the eye */
  uint8_t *seen;   /* nodes a cell: the exact tree's node accounted for by a piece */
  /* dispersion image solids (the plan's RT_EFFECT_DISPERSION) */
  int solids;         /* 1: white refractions into dispersive glass become solids */
  int collect;        /* 1: pieces and exact regions are recorded, not drawn */
  int sdepth;         /* the recorded paths' dispersive step */
  struct sd_rec *rec; /* the records of the solids' subtrees */
  int nrec, caprec;
  struct sd_entry *ent;     /* where white rays enter dispersive glass */
  int nent, capent, sentry; /* ... and the one being recorded */
  struct sd_pt *pt;         /* the entries' cell shares */
  int npt, cappt;
  bm_model_t *smod; /* their prefix models */
  int nmod, capmod;
  int oom;                     /* recording ran out of memory */
  int climit;                  /* records the solid being collected may still take */
  size_t *sused;               /* shared: bytes the solids hold (bt_options_t.memory_budget) */
  int *failed;                 /* shared: set past the budget, so that tiles left are skipped */
  const rt_material_t *sglass; /* the glass the solid's rays entered */
  double u[BT_SOLID_SEGS + 1]; /* the solids' breakpoints on the wavelength axis */
  const px_vec3_t *edge_in;    /* face edge e's inward normal at [face.first + e] */
  sd_fine_t *fine;             /* shared: groups known too fine */
} tile_t;

/* A region that the subtree of a solid traces exactly, recorded in place of a piece's face. */
#define BT_REC_EXACT (-9)

/* Every thread's solids, merged once all tiles are done (solids.c): records and their models,
 * entries, points, and the entries' groups. */
typedef struct {
  struct sd_rec *rec;
  int nrec, caprec;
  bm_model_t *mod;
  int nmod, capmod;
  struct sd_entry *ent;
  int nent, capent;
  struct sd_pt *pt;
  int npt, cappt;
  struct sd_group *grp;
  int ngrp;
  rt_rgb_t *light; /* each point's light, its share of its pixel */
  int failed;      /* a thread ran out of memory */
} sd_store_t;

/* render.c */
int bt__clip_box(const px_poly2_t *p, double x0, double x1, double y0, double y1, double *area,
                 double c[2]);
void bt__cell_range(const tile_t *T, const px_poly2_t *r, int *i0, int *i1, int *j0, int *j1);
int bt__inside(const px_poly2_t *r, const double p[2]);
rt_ray_kind_t bt__kind_of(const bm_step_t *st);
int bt__face_surface(const tile_t *T, const bm_face_t *f, const rt_ray_t *r, rt_surface_t *sf);
rt_ray_t bt__model_ray(const tile_t *T, const bm_model_t *m, const bm_path_t *path, int j,
                       const double p[2]);
int bt__model_weight(const tile_t *T, const bm_model_t *ms, const bm_path_t *path, int n,
                     const double p[2], rt_rgb_t *w);
int bt__exact_path(const tile_t *T, const bm_path_t *path, const double p[2], rt_ray_t *r,
                   rt_rgb_t *w);
double bt__index_at(const tile_t *T, const rt_material_t *m, double du);
int bt__exact_path_at(const tile_t *T, const bm_path_t *path, const double p[2], double du,
                      rt_ray_t *r, rt_rgb_t *w);
int bt__footprint(const tile_t *T, const bm_model_t *m, const bm_face_t *f, const double c[2],
                  px_vec3_t *u, px_vec3_t *v);
void bt__beam(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int splits, const int *faces,
              int nfaces, int level);

/* solids.c */
/* Record region r along path (a piece of face `face` with prefix models ms[0 .. path->n] and its
 * children's steps kid[0 .. nkid-1], or BT_REC_EXACT) in the solid being collected. */
void bt__solid_record(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int face,
                      const bm_model_t *ms, int nkid, const bm_step_t *kid);
/* Region r along path meets face g (surface sc at its centroid), where refraction st enters
 * dispersive glass: the subtree below recorded as solids and r's cell shares as points. */
void bt__solid(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int g, const bm_step_t *st,
               const rt_surface_t *sc, int splits, int level);
/* Inside bt_render()'s parallel region, every thread once its tiles are done: the threads'
 * solids merged into *all, grouped, and every point drawn and added to img (W x H pixels, s x s
 * cells each). 0 when out of memory (in any thread). */
int bt__solids_draw(tile_t *T, sd_store_t *all, rt_image_t *img, int W, int H, int s);
void bt__store_free(sd_store_t *all);

#endif
