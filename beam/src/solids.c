/* solids.c -- dispersion image solids in beam tracing from the eye ([P89] section 3.2;
 * docs/beam.md, "Dispersion"): the subtree below a white ray's refraction into dispersive glass
 * recorded as pieces, each swept along the wavelength axis, and every cell share of the entry
 * scan-converted along that axis once every tile is done. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/shade_paths.h"
#include "paraxial/dispersion.h"
#include "render_impl.h"

/* [P89] section 3.2. Where a white ray enters dispersive glass (an *entry*), every ray of the
 * subtree below depends on the wavelength too: in the pseudo-3D screen (the screen's parameters
 * and the plan's wavelength axis u, Lambda of the scene's one glass, 3.3) a piece of the subtree
 * is a solid whose slice at u is the piece's image at that wavelength. The subtree is partitioned
 * at u_c as the beam tree always is (its steps carry dn2) and its pieces and exact regions are
 * recorded instead of drawn. A piece's solid follows the points where its rays meet the faces of
 * its path below the entry: a face point moves with u as the exact ray of the piece's centroid
 * does (Eq. 15's shift of a polygon, rigid over the piece), traced at BT_SOLID_SEGS + 1
 * breakpoints and joined by chords. The entry's cell shares are points, drawn once every tile is
 * done from the records of every entry of the same path and face (its group: a solid sweeps
 * across tile edges), scan-converted along the axis (3.2.3): a piece covers the wavelengths at
 * which its points lie inside every face of its path; in each beam the nearest face is seen (the
 * three-dimensional clipping by a priority list, 3.2.2); a piece's light over its interval is its
 * direct term (cut at checker squares' edges) times its path's exact weights at the interval's
 * middle times the colour weights' integral; a beam's background takes what its faces leave.
 *
 * What the solids do not draw is traced by spectral pencils from the end of the beam's path
 * (remainder_exact()): the wavelengths of a piece whose solid failed its checks (and of its
 * subtree), of a beam with exact regions, of a gap over BT_SOLID_GAP in a beam without a
 * background, or where the path at p has no such child (total internal reflection). A point whose
 * candidates overflow is traced from the entry (solid_exact()), and so is every point of a group
 * in which one subtree held more pieces than its entry has points (too fine for solids to pay).
 * Not checked: a face that no piece of the subtree meets at u_c but that appears at another
 * wavelength beside a background (its light is drawn as the background's), and shadows that
 * differ along an interval (the direct term is taken at its middle). */

/* Overlap or gap between a beam's wavelengths and its pieces' tolerated at a point, as a share
 * of the visible range. */
#define BT_SOLID_GAP 0.02
/* Faces a recorded path may meet (its shifts' table): a subtree with deeper paths is traced (a
 * record takes about 3 KB and its models; the scenes' depth limit is 6 by default). */
#define BT_SOLID_LEVELS 12
/* Records a solid's subtree may take beyond one a point: more, and its pieces are too small
 * against the cells for solids to pay (as a beam that is too dense is traced, render.c). */
#define BT_SOLID_FEW 16
/* Candidates (pieces of distinct paths and faces) at one point, and intervals a list holds. */
#define BT_SOLID_CAND 256
#define BT_IV_MAX 16
/* Largest departure of a path's weights (any channel) from linear in u, between breakpoints or
 * over an interval traced exactly, before they are taken as linear there. */
#define BT_SOLID_WTOL 0.01
/* A remainder's first ray whose linear model errs by less than this many pixels, seen from the
 * eye, at its interval's ends needs no halving (wpencil.c's WP_PIXELS). */
#define BT_SOLID_PIXELS 0.25
/* Halvings of an interval traced exactly where a path's weights are not yet linear. */
#define BT_SOLID_HALVINGS 8
/* Checker squares' edges an interval is cut at, at most (a piece's point crossing more squares
 * than this keeps the rest's colour of the last). */
#define BT_SOLID_CUTS 32

typedef struct sd_rec {
  bm_path_t path;
  int face;          /* the face its rays meet (-1: none); BT_REC_EXACT: traced exactly */
  px_poly2_t region; /* its polygon at u_c */
  double c[2];       /* its centroid */
  double box[4];     /* what its solid may cover: lo x, hi x, lo y, hi y */
  int model;         /* its path.n + 1 prefix models from T->smod[model] */
  int ok;            /* 1: its solid passed the checks */
  int failed;        /* 1: its solid was made and failed them */
  int entry;         /* its entry (sd_entry_t) */
  uint64_t key;      /* a hash of its path and face (same_key()) */
  double rbox[4];    /* its region's box */
  int nkid;          /* its children at u_c (a piece of a face) */
  bm_step_t kid[2];  /* their steps */
  int kdark[2];      /* 1: no light follows kid k anywhere in box (kid_dark()) */
  rt_rgb_t wb[BT_SOLID_SEGS + 1]; /* its path's weights at the breakpoints, centroid's ray */
  int wok;                        /* 1: its weights by weight_at() in wbox (weight_model()) */
  double wbox[4];                 /* where: lo x, hi x, lo y, hi y */
  rt_rgb_t wgx, wgy;              /* their gradient in the parameters at u_c */
  /* depth j's point (the face of step j, or `face` for j = path.n) at breakpoint k less its
   * point at u_c, for the centroid's exact ray */
  px_vec3_t shift[BT_SOLID_LEVELS][BT_SOLID_SEGS + 1];
} sd_rec_t;

/* Where a white ray enters dispersive glass: a piece's region r (its cell shares are the points
 * drawn from the solids), the path to its face g and the refraction. Entries of one path and face
 * (in every tile) form a group whose records serve each other's points. */
typedef struct sd_entry {
  bm_path_t path;
  int g;
  bm_step_t st;
  const rt_material_t *glass;
  double box[4]; /* r's box: lo x, hi x, lo y, hi y */
  int first;     /* its records from here (the recording thread's) */
  int bad;       /* its points are traced: 1 recording ran out of memory, 2 its subtree was too fine
                    for solids, 3 another entry of its group was */
  int group;
} sd_entry_t;

/* A cell share of an entry's region: drawn once every tile is done. */
typedef struct sd_pt {
  int entry;
  int cx, cy;  /* the cell, in the image's cells */
  double frac; /* the share's area over the cell's */
  double p[2]; /* its centroid: the point drawn */
} sd_pt_t;

/* The records of one group, binned by their boxes on a grid of cells gcell wide from (gx0, gy0):
 * cell c's records are list[start[c] .. start[c + 1] - 1]. */
typedef struct sd_group {
  int entry; /* one of its entries */
  double gx0, gy0, gcell;
  int gw, gh;
  int *start, *list;
} sd_group_t;

/* A list of disjoint increasing intervals of u. */
typedef struct {
  int n;
  double a[BT_IV_MAX], b[BT_IV_MAX];
} sd_iv_t;

/* *dst = *src, its intervals alone. */
static void iv_copy(sd_iv_t *dst, const sd_iv_t *src) {
  dst->n = src->n;
  for (int k = 0; k < src->n; k++) {
    dst->a[k] = src->a[k];
    dst->b[k] = src->b[k];
  }
}

static double iv_len(const sd_iv_t *v) {
  double l = 0.0;
  for (int k = 0; k < v->n; k++)
    l += v->b[k] - v->a[k];
  return l;
}

/* Append [a, b] to v (increasing a), merged with the last interval when they touch. 0 when full. */
static int iv_add(sd_iv_t *v, double a, double b) {
  if (!(b > a))
    return 1;
  if (v->n > 0 && a <= v->b[v->n - 1]) {
    v->b[v->n - 1] = fmax(v->b[v->n - 1], b);
    return 1;
  }
  if (v->n == BT_IV_MAX)
    return 0;
  v->a[v->n] = a;
  v->b[v->n++] = b;
  return 1;
}

/* [a, b] into v wherever it falls (v stays increasing; touching intervals merge). 0 when full. */
static int iv_insert(sd_iv_t *v, double a, double b) {
  sd_iv_t out;
  out.n = 0;
  int done = 0;
  for (int k = 0; k <= v->n; k++) {
    if (!done && (k == v->n || a < v->a[k])) {
      if (!iv_add(&out, a, b))
        return 0;
      done = 1;
    }
    if (k < v->n && !iv_add(&out, v->a[k], v->b[k]))
      return 0;
  }
  iv_copy(v, &out);
  return 1;
}

/* v less [a, b] into *out. 0 when out is full. */
static int iv_cut(const sd_iv_t *v, double a, double b, sd_iv_t *out) {
  out->n = 0;
  for (int k = 0; k < v->n; k++)
    if (!iv_add(out, v->a[k], fmin(v->b[k], a)) || !iv_add(out, fmax(v->a[k], b), v->b[k]))
      return 0;
  return 1;
}

/* Grow array *a of *cap elements of `size` to hold n; 0 when out of memory. */
static int grow(void **a, int *cap, int n, size_t size) {
  if (n <= *cap)
    return 1;
  int c = *cap ? *cap : 64;
  while (c < n)
    c *= 2;
  void *q = realloc(*a, (size_t)c * size);
  if (!q)
    return 0;
  *a = q;
  *cap = c;
  return 1;
}

/* FNV-1a over steps[0 .. n-1]'s faces and events, continued from h (bt__solid_record()'s key
 * without its face): equal for equal steps. */
static uint64_t steps_hash(uint64_t h, const bm_step_t *steps, int n) {
  for (int k = 0; k < n; k++)
    h = (h ^ (uint64_t)(steps[k].face * 2 + (int)steps[k].event)) * 1099511628211ULL;
  return h;
}
#define SD_FNV_BASIS 1469598103934665603ULL

/* Count n bytes more held by the solids (twice what a thread appends: its arrays are copied once
 * more when merged); 0, with T->oom set, past bt_options_t.memory_budget. n may be negative (what
 * a thread gives back). */
static int spend(tile_t *T, long long n) {
  if (!T->o->memory_budget)
    return 1;
  size_t now, d = (size_t)(2 * (n < 0 ? -n : n));
  if (n < 0) {
#pragma omp atomic update
    *T->sused -= d;
    return 1;
  }
#pragma omp atomic capture
  now = *T->sused += d;
  if (now <= T->o->memory_budget)
    return 1;
  T->oom = 1;
  T->st.solid_over_budget = 1;
  if (T->failed) { /* the render fails: the tiles left are not traced */
#pragma omp atomic write
    *T->failed = 1;
  }
  return 0;
}

void bt__solid_record(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int face,
                      const bm_model_t *ms, int nkid, const bm_step_t *kid) {
  if (T->oom || T->climit <= 0)
    return;
  T->climit = path->n < BT_SOLID_LEVELS ? T->climit - 1 : 0; /* too deep: give the solid up */
  if (T->climit <= 0)
    return;
  int nm = ms ? path->n + 1 : 0;
  if (!spend(T, (long long)(sizeof *T->rec + (size_t)nm * sizeof *T->smod)))
    return;
  if (!grow((void **)&T->rec, &T->caprec, T->nrec + 1, sizeof *T->rec) ||
      !grow((void **)&T->smod, &T->capmod, T->nmod + nm, sizeof *T->smod)) {
    T->oom = 1;
    return;
  }
  sd_rec_t *q = &T->rec[T->nrec++];
  q->entry = T->sentry;
  q->path = *path;
  q->face = face;
  /* FNV-1a over the steps' faces and events, and face */
  q->key =
      (steps_hash(SD_FNV_BASIS, path->step, path->n) ^ (uint64_t)(int64_t)face) * 1099511628211ULL;
  q->region = *r;
  q->ok = q->wok = q->failed = q->kdark[0] = q->kdark[1] = 0;
  q->nkid = nkid;
  for (int k = 0; k < nkid; k++)
    q->kid[k] = kid[k];
  q->model = T->nmod;
  if (nm) {
    memcpy(T->smod + T->nmod, ms, (size_t)nm * sizeof *ms);
    T->nmod += nm;
  }
  if (px_poly2_centroid(r, q->c) != PX_OK) {
    q->c[0] = r->v[0][0];
    q->c[1] = r->v[0][1];
  }
}

/* The face a record's rays meet at depth j (step j's, or its own at j = path.n; NULL for none). */
static const bm_face_t *rec_face(const tile_t *T, const sd_rec_t *q, int j) {
  int f = j < q->path.n ? q->path.step[j].face : q->face;
  return f >= 0 ? &T->b->face[f] : NULL;
}

/* The points of the exact ray of parameters p along q's path at u: pts[j] for every depth j
 * whose face exists (rec_face()). 0 when it misses a plane or is totally reflected. */
static int rec_points(const tile_t *T, const sd_rec_t *q, const double p[2], double u,
                      px_vec3_t *pts) {
  px_vec3_t o, d;
  double uc = T->u[BT_SOLID_SEGS / 2];
  if (bm_exact_at(T->b, &T->src, &q->path, p, u - uc, pts, &o, &d) != PX_OK)
    return 0;
  const bm_face_t *f = rec_face(T, q, q->path.n);
  if (!f)
    return 1;
  double den = px_v3_dot(f->n, d), t = (f->d - px_v3_dot(f->n, o)) / den;
  if (!(den != 0.0) || !(t > 0.0) || !isfinite(t))
    return 0;
  pts[q->path.n] = px_v3_axpy(t, d, o);
  return 1;
}

/* Depth j's point at u of q's solid over the model point x0 (its point at u_c). */
static px_vec3_t rec_at(const tile_t *T, const sd_rec_t *q, int j, px_vec3_t x0, double u) {
  int k = 0;
  while (k < BT_SOLID_SEGS - 1 && u > T->u[k + 1])
    k++;
  double f = (u - T->u[k]) / (T->u[k + 1] - T->u[k]);
  px_vec3_t s = px_v3_add(px_v3_scale(q->shift[j][k], 1.0 - f), px_v3_scale(q->shift[j][k + 1], f));
  return px_v3_add(x0, s);
}

/* The largest difference of a and b in any channel. */
static double rgb_dist(rt_rgb_t a, rt_rgb_t b) {
  return fmax(fabs(a.r - b.r), fmax(fabs(a.g - b.g), fabs(a.b - b.b)));
}

/* The box of polygon r: lo[0], lo[1] and hi[0], hi[1]. */
static void poly_box(const px_poly2_t *r, double lo[2], double hi[2]) {
  lo[0] = lo[1] = INFINITY;
  hi[0] = hi[1] = -INFINITY;
  for (int k = 0; k < r->n; k++)
    for (int a = 0; a < 2; a++) {
      lo[a] = fmin(lo[a], r->v[k][a]);
      hi[a] = fmax(hi[a], r->v[k][a]);
    }
}

/* The weights' model of record q (its path's weights at point p and wavelength offset u - u_c):
 * the centroid's weights at the breakpoints, linear between them, plus a gradient in the
 * parameters fitted to the corners of a box around the centroid. It is tried on the box its solid
 * may cover, then on its region's box widened by a pixel; q->wbox is the first box on which the
 * model is within BT_SOLID_WTOL of the exact weights at every corner and breakpoint (its chords at
 * the centroid are checked by solid_prepare()). Points outside it, and every point where no box
 * passes (q->wok 0: an exact path fails at a corner, by total internal reflection, or the model is
 * off), trace the weights (bt__exact_path_at()), and so does every point of a path with a step on
 * a checkered object (its squares' materials may split light differently). A quadratic change
 * over the box departs from the model most at its corners; not checked: a change of higher order
 * (a Fresnel weight near the critical angle) and total internal reflection that begins and ends
 * between a corner's breakpoints. */
static int weight_fit(tile_t *T, sd_rec_t *q, const double box[4]) {
  int mid = BT_SOLID_SEGS / 2;
  rt_rgb_t w[4][BT_SOLID_SEGS + 1];
  double cx[4], cy[4];
  double dx = box[1] - box[0], dy = box[3] - box[2];
  if (!(dx > 0.0) || !(dy > 0.0))
    return 0;
  for (int i = 0; i < 4; i++) {
    cx[i] = box[i & 1];
    cy[i] = box[2 + (i >> 1)];
    double p[2] = {cx[i], cy[i]};
    for (int k = 0; k <= BT_SOLID_SEGS; k++) {
      rt_ray_t ray;
      if (!bt__exact_path_at(T, &q->path, p, T->u[k] - T->u[mid], &ray, &w[i][k]))
        return 0;
    }
  }
  /* the least-squares plane through the corners: the mean slope along each axis */
  q->wgx = rt_rgb_scale(
      rt_rgb_madd(rt_rgb_add(w[1][mid], w[3][mid]), -1.0, rt_rgb_add(w[0][mid], w[2][mid])),
      0.5 / dx);
  q->wgy = rt_rgb_scale(
      rt_rgb_madd(rt_rgb_add(w[2][mid], w[3][mid]), -1.0, rt_rgb_add(w[0][mid], w[1][mid])),
      0.5 / dy);
  for (int i = 0; i < 4; i++)
    for (int k = 0; k <= BT_SOLID_SEGS; k++) {
      rt_rgb_t m =
          rt_rgb_madd(rt_rgb_madd(q->wb[k], cx[i] - q->c[0], q->wgx), cy[i] - q->c[1], q->wgy);
      if (!(rgb_dist(m, w[i][k]) <= BT_SOLID_WTOL))
        return 0;
    }
  memcpy(q->wbox, box, sizeof q->wbox);
  return 1;
}

static void weight_model(tile_t *T, sd_rec_t *q) {
  double near[4] = {q->rbox[0] - T->pixel, q->rbox[1] + T->pixel, q->rbox[2] - T->pixel,
                    q->rbox[3] + T->pixel};
  q->wok = 0;
  for (int j = 0; j < q->path.n; j++) /* a checkered step: weights that jump between squares */
    if (T->s->object[T->b->face[q->path.step[j].face].object].material2 >= 0)
      return;
  q->wok = weight_fit(T, q, q->box) || weight_fit(T, q, near);
}

/* 1 when no light follows record q's child k anywhere its solid may be seen: its exact path
 * fails (total internal reflection) at the centroid and every corner of q's box at every
 * breakpoint. A child kept for the wavelengths at which it exists (render.c, leaving dispersive
 * glass) then needs no exact rays at its points. Not checked: a child that exists only between
 * the samples. */
static int kid_dark(tile_t *T, const sd_rec_t *q, int k) {
  bm_path_t bp = q->path;
  bp.step[bp.n++] = q->kid[k];
  int mid = BT_SOLID_SEGS / 2;
  for (int i = 0; i < 5; i++) { /* the centroid first, and u_c first: a child that exists there */
    double p[2] = {i ? q->box[(i - 1) & 1] : q->c[0], i ? q->box[2 + ((i - 1) >> 1)] : q->c[1]};
    for (int j = 0; j <= BT_SOLID_SEGS; j++) {
      int b = (mid + j) % (BT_SOLID_SEGS + 1);
      rt_ray_t ray;
      rt_rgb_t w;
      if (bt__exact_path_at(T, &bp, p, T->u[b] - T->u[mid], &ray, &w))
        return 0;
    }
  }
  return 1;
}

/* 1 when record q's weights at point p are its model's (weight_model()). */
static int weight_held(const sd_rec_t *q, const double p[2]) {
  return q->wok && p[0] >= q->wbox[0] && p[0] <= q->wbox[1] && p[1] >= q->wbox[2] &&
         p[1] <= q->wbox[3];
}

/* Record q's path's weights at point p and wavelength u by its model (weight_held()). */
static rt_rgb_t weight_at(const tile_t *T, const sd_rec_t *q, const double p[2], double u) {
  int k = 0;
  while (k < BT_SOLID_SEGS - 1 && u > T->u[k + 1])
    k++;
  double f = (u - T->u[k]) / (T->u[k + 1] - T->u[k]);
  rt_rgb_t w = rt_rgb_add(rt_rgb_scale(q->wb[k], 1.0 - f), rt_rgb_scale(q->wb[k + 1], f));
  return rt_rgb_madd(rt_rgb_madd(w, p[0] - q->c[0], q->wgx), p[1] - q->c[1], q->wgy);
}

/* Record q's solid: the shifts and weights at the breakpoints, its box (the region's, widened by
 * the largest shift and a pixel; returned, in parameters), and its checks: the weights and the
 * chords halfway between breakpoints at the centroid, and the solid at the range's ends against
 * exact rays at the region's vertices, within rho pixel intervals. A solid that fails them keeps
 * its box with ok 0 (where it is a candidate its beam's rest is traced exactly); one whose
 * centroid's rays cannot be traced keeps an empty box (lo > hi) and returns 0. */
static double solid_prepare(tile_t *T, sd_rec_t *q) {
  double lo[2], hi[2];
  poly_box(&q->region, lo, hi);
  q->rbox[0] = lo[0];
  q->rbox[1] = hi[0];
  q->rbox[2] = lo[1];
  q->rbox[3] = hi[1];
  q->ok = 0;
  q->box[0] = q->box[2] = INFINITY;
  q->box[1] = q->box[3] = -INFINITY;
  if (q->face == BT_REC_EXACT) {
    q->box[0] = lo[0];
    q->box[1] = hi[0];
    q->box[2] = lo[1];
    q->box[3] = hi[1];
    q->ok = 1;
    return 0.0;
  }
  int n = q->path.n, d = T->sdepth, mid = BT_SOLID_SEGS / 2;
  const bm_model_t *ms = T->smod + q->model;
  px_vec3_t pts[BT_SOLID_SEGS + 1][BT_LEVELS], half[BT_SOLID_SEGS][BT_LEVELS];
  rt_ray_t ray;
  rt_rgb_t wh[BT_SOLID_SEGS];
  for (int k = 0; k <= BT_SOLID_SEGS; k++)
    if (!rec_points(T, q, q->c, T->u[k], pts[k]) ||
        !bt__exact_path_at(T, &q->path, q->c, T->u[k] - T->u[mid], &ray, &q->wb[k]))
      return 0.0;
  for (int k = 0; k < BT_SOLID_SEGS; k++) {
    double u = 0.5 * (T->u[k] + T->u[k + 1]);
    if (!rec_points(T, q, q->c, u, half[k]) ||
        !bt__exact_path_at(T, &q->path, q->c, u - T->u[mid], &ray, &wh[k]))
      return 0.0;
  }
  px_vec3_t fu[BT_LEVELS], fv[BT_LEVELS];
  double reach = 0.0; /* the largest shift, pixel intervals */
  for (int j = d + 1; j <= n; j++) {
    const bm_face_t *f = rec_face(T, q, j);
    if (!f)
      continue;
    if (!bt__footprint(T, &ms[j], f, q->c, &fu[j], &fv[j]))
      return 0.0;
    for (int k = 0; k <= BT_SOLID_SEGS; k++) {
      q->shift[j][k] = px_v3_sub(pts[k][j], pts[mid][j]);
      reach =
          fmax(reach, hypot(px_v3_dot(fu[j], q->shift[j][k]), px_v3_dot(fv[j], q->shift[j][k])));
    }
  }
  double grow = (reach + 1.0) * T->pixel;
  q->box[0] = lo[0] - grow;
  q->box[1] = hi[0] + grow;
  q->box[2] = lo[1] - grow;
  q->box[3] = hi[1] + grow;
  q->failed = 1;                          /* until the checks pass */
  for (int k = 0; k < BT_SOLID_SEGS; k++) /* the weights linear between breakpoints */
    if (rgb_dist(rt_rgb_scale(rt_rgb_add(q->wb[k], q->wb[k + 1]), 0.5), wh[k]) > BT_SOLID_WTOL)
      return grow;
  for (int j = d + 1; j <= n; j++) {
    const bm_face_t *f = rec_face(T, q, j);
    if (!f)
      continue;
    for (int k = 0; k < BT_SOLID_SEGS; k++) { /* the chords halfway, at the centroid */
      px_vec3_t e = px_v3_sub(px_v3_scale(px_v3_add(pts[k][j], pts[k + 1][j]), 0.5), half[k][j]);
      if (!(hypot(px_v3_dot(fu[j], e), px_v3_dot(fv[j], e)) <= T->o->rho))
        return grow;
    }
    /* the solid at the range's ends against exact rays at the region's vertices */
    for (int v = 0; v < q->region.n; v++)
      for (int k = 0; k <= BT_SOLID_SEGS; k += BT_SOLID_SEGS) {
        px_vec3_t ex[BT_LEVELS], x0;
        double sd;
        T->st.checks++;
        if (!rec_points(T, q, q->region.v[v], T->u[k], ex) ||
            bm_model_hit(&ms[j], &T->src, q->region.v[v], f->n, f->d, &x0, &sd) != PX_OK)
          return grow;
        px_vec3_t e = px_v3_sub(rec_at(T, q, j, x0, T->u[k]), ex[j]);
        if (!(hypot(px_v3_dot(fu[j], e), px_v3_dot(fv[j], e)) <= T->o->rho))
          return grow;
      }
  }
  q->failed = 0;
  q->ok = 1;
  weight_model(T, q);
  for (int k = 0; k < q->nkid; k++)
    q->kdark[k] = kid_dark(T, q, k);
  return grow;
}

/* 1 when paths a and b meet the same faces with the same events. */
static int same_steps(const bm_path_t *a, const bm_path_t *b) {
  if (a->n != b->n)
    return 0;
  for (int k = 0; k < a->n; k++)
    if (a->step[k].face != b->step[k].face || a->step[k].event != b->step[k].event)
      return 0;
  return 1;
}

/* 1 when records a and b follow one path. */
static int same_path(const sd_rec_t *a, const sd_rec_t *b) {
  return same_steps(&a->path, &b->path);
}

/* 1 when records a and b are of one path and one face (pieces a division cut apart). */
static int same_key(const sd_rec_t *a, const sd_rec_t *b) {
  return a->face == b->face && same_path(a, b);
}

/* The wavelengths at which point p lies in piece q's solid (its points inside every face of its
 * path below the entry) into *out. 0 when a model has no point there. */
static int solid_intervals(const tile_t *T, const sd_rec_t *q, const double p[2], sd_iv_t *out) {
  int n = q->path.n;
  const bm_model_t *ms = T->smod + q->model;
  double lo[BT_SOLID_SEGS], hi[BT_SOLID_SEGS];
  for (int k = 0; k < BT_SOLID_SEGS; k++) {
    lo[k] = T->u[k];
    hi[k] = T->u[k + 1];
  }
  for (int j = T->sdepth + 1; j <= n; j++) {
    const bm_face_t *f = rec_face(T, q, j);
    if (!f || f->count == 0)
      continue;
    px_vec3_t x0;
    double sd;
    if (bm_model_hit(&ms[j], &T->src, p, f->n, f->d, &x0, &sd) != PX_OK)
      return 0;
    const px_vec3_t *v = T->b->vertex + f->first;
    for (int e = 0; e < f->count; e++) {
      px_vec3_t in = T->edge_in[f->first + e];
      /* in . (point - v[e]) >= 0 inside, linear in u on each segment */
      double base = px_v3_dot(in, px_v3_sub(x0, v[e])), g[BT_SOLID_SEGS + 1];
      for (int k = 0; k <= BT_SOLID_SEGS; k++)
        g[k] = base + px_v3_dot(in, q->shift[j][k]);
      for (int k = 0; k < BT_SOLID_SEGS; k++) {
        if (!(hi[k] > lo[k]))
          continue;
        double g0 = g[k], g1 = g[k + 1];
        if (g0 >= 0.0 && g1 >= 0.0)
          continue;
        if (g0 < 0.0 && g1 < 0.0) {
          hi[k] = lo[k];
          continue;
        }
        double cut = T->u[k] + (T->u[k + 1] - T->u[k]) * g0 / (g0 - g1);
        if (g0 >= 0.0)
          hi[k] = fmin(hi[k], cut);
        else
          lo[k] = fmax(lo[k], cut);
      }
    }
  }
  out->n = 0;
  for (int k = 0; k < BT_SOLID_SEGS; k++)
    if (!iv_add(out, lo[k], hi[k]))
      return 0;
  return 1;
}

/* The light of piece q (a face) at point p over [a, b] along ray's direction from x0 (its model
 * point at u_c): the direct term where its point meets the face, times the colour weights'
 * integral ([P89] 3.2.3's R = int t r L dlambda with L constant). On a checkerboard the interval is
 * cut where its point crosses a square's edge (the chords between breakpoints cross the grid's
 * lines at wavelengths found exactly), each part shaded at its middle. */
static rt_rgb_t solid_light(tile_t *T, const sd_rec_t *q, const rt_ray_t *ray, px_vec3_t x0,
                            double a, double b) {
  const bm_face_t *f = rec_face(T, q, q->path.n);
  const rt_prim_t *pr = &T->s->prim[f->prim];
  int n = q->path.n, checker = T->s->object[pr->object].material2 >= 0 && pr->kind == RT_PRIM_PLANE;
  double cut[BT_SOLID_CUTS + 2];
  int nc = 0;
  cut[nc++] = a;
  for (int k = 0; checker && k < BT_SOLID_SEGS; k++) {
    double lo = fmax(a, T->u[k]), hi = fmin(b, T->u[k + 1]);
    if (!(hi > lo))
      continue;
    double c0[2], c1[2], inv = pr->plane.inv_check;
    rt_plane_coords(&pr->plane, rec_at(T, q, n, x0, lo), &c0[0], &c0[1]);
    rt_plane_coords(&pr->plane, rec_at(T, q, n, x0, hi), &c1[0], &c1[1]);
    for (int ax = 0; ax < 2; ax++) { /* the grid's lines between the ends, linear in u */
      double g0 = c0[ax] * inv, g1 = c1[ax] * inv;
      for (double l = floor(fmin(g0, g1)) + 1.0; l <= fmax(g0, g1) && nc <= BT_SOLID_CUTS; l++)
        cut[nc++] = lo + (hi - lo) * (l - g0) / (g1 - g0);
    }
  }
  for (int k = 1; k < nc; k++) /* insertion sort: a handful */
    for (int m = k; m > 1 && cut[m] < cut[m - 1]; m--) {
      double t = cut[m];
      cut[m] = cut[m - 1];
      cut[m - 1] = t;
    }
  cut[nc++] = b;
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  for (int k = 0; k + 1 < nc; k++) {
    if (!(cut[k + 1] > cut[k]))
      continue;
    px_vec3_t x = rec_at(T, q, n, x0, 0.5 * (cut[k] + cut[k + 1]));
    rt_hit_t h = {px_v3_norm(px_v3_sub(x, ray->o)), x, f->n, f->prim, f->object};
    rt_surface_t sf;
    rt_shade_surface(T->s, &h, ray, &sf);
    T->ex.node = -1;
    rt_rgb_t L = rt_shade_direct(T->s, T->plan, &sf, ray, &T->tr);
    sum = rt_rgb_add(sum, rt_rgb_mul(L, rt_wave_weight(&T->plan->wave, cut[k], cut[k + 1])));
  }
  return sum;
}

/* 1 when record a is an ancestor of record b: b's path runs through a's face. */
static int ancestor_of(const sd_rec_t *a, const sd_rec_t *b) {
  int n = a->path.n;
  if (a->face < 0 || b->path.n <= n || b->path.step[n].face != a->face)
    return 0;
  for (int k = 0; k < n; k++)
    if (a->path.step[k].face != b->path.step[k].face ||
        a->path.step[k].event != b->path.step[k].event)
      return 0;
  return 1;
}

/* The light that leaves the end of path bp at point p over [a, b], traced exactly by a spectral
 * pencil (rt_shade_spectral_ray()), its column from exact rays a little either side of the
 * interval's centre, weighted by the path's weights at the centre (bt__exact_path_at()). Halved
 * while the path's weights at a, b and the centre are not nearly linear (a step's total internal
 * reflection or its Fresnel weight turning inside), `depth` halvings at most. 0 when an exact ray
 * misses a face. */
static int remainder_exact(tile_t *T, const bm_path_t *bp, const double p[2], double a, double b,
                           int depth, rt_rgb_t *light) {
  double uc = T->u[BT_SOLID_SEGS / 2], um = 0.5 * (a + b);
  double h = 1e-3 * (T->u[BT_SOLID_SEGS] - T->u[0]);
  const double us[3] = {a, um, b};
  rt_ray_t ray[3];
  rt_rgb_t w[3];
  int ok[3];
  for (int e = 0; e < 3; e++)
    ok[e] = bt__exact_path_at(T, bp, p, us[e] - uc, &ray[e], &w[e]);
  if (!ok[0] && !ok[1] && !ok[2])
    return 1; /* no light comes along the path at these wavelengths */
  rt_rgb_t lin = rt_rgb_scale(rt_rgb_add(w[0], w[2]), 0.5);
  if (depth > 0 && (!ok[0] || !ok[1] || !ok[2] || rgb_dist(lin, w[1]) > BT_SOLID_WTOL))
    return remainder_exact(T, bp, p, a, um, depth - 1, light) &&
           remainder_exact(T, bp, p, um, b, depth - 1, light);
  if (!ok[1])
    return 1;
  const rt_material_t *inside = NULL;
  for (int k = bp->n - 1; k >= 0; k--)
    if (bp->step[k].event == PX_EVENT_REFRACT) {
      inside = bp->step[k].dn2 != 0.0 ? T->sglass : NULL;
      break;
    }
  px_vec3_t o[2], d[2];
  for (int e = 0; e < 2; e++)
    if (bm_exact_at(T->b, &T->src, bp, p, um - uc + (2 * e - 1) * h, NULL, &o[e], &d[e]) != PX_OK)
      return 0;
  px_vec3_t d_o = px_v3_scale(px_v3_sub(o[1], o[0]), 0.5 / h);
  px_vec3_t d_d = px_v3_scale(px_v3_sub(d[1], d[0]), 0.5 / h);
  /* the pencil's linear model of its first ray at the interval's ends against the exact rays
   * there, as white() checks the refraction it starts from (core/src/wpencil.c) */
  for (int e = 0; e < 3 && depth > 0; e += 2) {
    double du = us[e] - um, shift = px_v3_norm(d_d) * fabs(du);
    px_vec3_t dm = px_v3_unit(px_v3_axpy(du, d_d, ray[1].d));
    if (px_v3_norm(px_v3_sub(dm, ray[e].d)) >
        fmax(T->plan->spectral_tol * shift, BT_SOLID_PIXELS * T->plan->pixel_angle))
      return remainder_exact(T, bp, p, a, um, depth - 1, light) &&
             remainder_exact(T, bp, p, um, b, depth - 1, light);
  }
  T->st.solid_traced++;
  rt_rgb_t L = rt_shade_spectral_ray(T->s, T->plan, &ray[1], d_o, d_d, a, b, inside, T->sglass,
                                     rt_rgb_max(w[1]), bp->n, &T->tr);
  *light = rt_rgb_add(*light, rt_rgb_mul(w[1], L));
  return 1;
}

/* v less every interval of w, into *out. 0 when out is full. */
static int iv_minus(const sd_iv_t *v, const sd_iv_t *w, sd_iv_t *out) {
  sd_iv_t cur, next;
  iv_copy(&cur, v);
  for (int k = 0; k < w->n; k++) {
    if (!iv_cut(&cur, w->a[k], w->b[k], &next))
      return 0;
    iv_copy(&cur, &next);
  }
  iv_copy(out, &cur);
  return 1;
}

/* v within w, into *out. 0 when out is full. */
static int iv_within(const sd_iv_t *v, const sd_iv_t *w, sd_iv_t *out) {
  out->n = 0;
  for (int i = 0; i < v->n; i++)
    for (int k = 0; k < w->n; k++)
      if (!iv_add(out, fmax(v->a[i], w->a[k]), fmin(v->b[i], w->b[k])))
        return 0;
  return 1;
}

/* 1 when path a begins with path pre followed by step last. */
static int below(const bm_path_t *a, const bm_path_t *pre, const bm_step_t *last) {
  int n = pre->n;
  if (a->n < n + 1 || a->step[n].face != last->face || a->step[n].event != last->event)
    return 0;
  for (int k = 0; k < n; k++)
    if (a->step[k].face != pre->step[k].face || a->step[k].event != pre->step[k].event)
      return 0;
  return 1;
}

/* 1 when path a is path pre followed by step last. */
static int follows(const bm_path_t *a, const bm_path_t *pre, const bm_step_t *last) {
  return a->n == pre->n + 1 && below(a, pre, last);
}

/* One beam of the solid's subtree at point p: the candidates cand[0 .. nc-1] (their paths'
 * steps_hash() in phash) that follow path pre and then step last, its path (state[c] 1 once
 * claimed, -1 dropped), whose wavelengths lie in pi (the parent piece's visible ones at p, or the
 * whole range at the entry). Hidden surfaces are removed along the wavelength axis, [P89] 3.2.2's
 * three-dimensional clipping by a priority list: at each wavelength the nearest piece's face (by
 * its point at u_c) is seen; iv[c] becomes what piece c shows, its light goes into *light. The
 * rest of pi (the background's, or traced exactly where a piece was dropped, the beam has exact
 * regions, or a gap over BT_SOLID_GAP opens) too. 0 when an exact ray of the rest misses. */
static int solid_beam(tile_t *T, const double p[2], const bm_path_t *pre, const bm_step_t *last,
                      const sd_iv_t *pi, const int *cand, const uint64_t *phash, sd_iv_t *iv,
                      int *state, int nc, rt_rgb_t *light) {
  double range = T->u[BT_SOLID_SEGS] - T->u[0];
  int bg = 0, exact = 0, mem[BT_SOLID_CAND], nm = 0, first = -1;
  double depth[BT_SOLID_CAND];
  px_vec3_t at[BT_SOLID_CAND];
  rt_ray_t ray[BT_SOLID_CAND];
  uint64_t h = steps_hash(steps_hash(SD_FNV_BASIS, pre->step, pre->n), last, 1);
  for (int c = 0; c < nc; c++) {
    const sd_rec_t *q = &T->rec[cand[c]];
    if (phash[c] != h || !follows(&q->path, pre, last)) /* the hash first: no record read */
      continue;
    if (state[c] < 0) {
      exact = 1; /* a dropped piece's wavelengths are traced */
      continue;
    }
    state[c] = 1;
    if (q->face < 0) {
      exact |= q->face == BT_REC_EXACT;
      if (q->face == -1)
        bg = c + 1;
      continue;
    }
    if (iv[c].n == 0)
      continue;
    const bm_model_t *qm = T->smod + q->model;
    const bm_face_t *f = rec_face(T, q, q->path.n);
    double sd;
    ray[c] = bt__model_ray(T, &qm[q->path.n], &q->path, q->path.n, p);
    if (bm_model_hit(&qm[q->path.n], &T->src, p, f->n, f->d, &at[c], &sd) != PX_OK)
      return 0;
    /* the depth of its face's plane along one ray for all: the first member's model ray */
    if (first < 0)
      first = c;
    const rt_ray_t *r0 = &ray[first];
    double den = px_v3_dot(f->n, r0->d);
    depth[c] = den != 0.0 ? (f->d - px_v3_dot(f->n, r0->o)) / den : INFINITY;
    int k = nm++; /* by depth, nearest first */
    for (; k > 0 && depth[mem[k - 1]] > depth[c]; k--)
      mem[k] = mem[k - 1];
    mem[k] = c;
  }
  sd_iv_t rest, next, redo;
  iv_copy(&rest, pi);
  redo.n = 0;
  double uc = T->u[BT_SOLID_SEGS / 2];
  for (int m = 0; m < nm; m++) {
    int c = mem[m];
    const sd_rec_t *q = &T->rec[cand[c]];
    if (!iv_within(&iv[c], &rest, &next))
      return 0;
    iv_copy(&iv[c], &next); /* what it shows: in pi, and not behind a nearer piece */
    if (!iv_minus(&rest, &iv[c], &next))
      return 0;
    iv_copy(&rest, &next);
    for (int k = 0; k < iv[c].n; k++) {
      /* the path's exact weights at p in the interval's middle; where p's path has no such
       * child there (total internal reflection), the interval is traced */
      rt_ray_t r;
      rt_rgb_t w;
      double um = 0.5 * (iv[c].a[k] + iv[c].b[k]);
      if (weight_held(q, p))
        w = weight_at(T, q, p, um);
      else if (!bt__exact_path_at(T, &q->path, p, um - uc, &r, &w)) {
        if (!iv_insert(&redo, iv[c].a[k], iv[c].b[k]))
          return 0;
        continue;
      }
      *light = rt_rgb_add(*light,
                          rt_rgb_mul(w, solid_light(T, q, &ray[c], at[c], iv[c].a[k], iv[c].b[k])));
    }
  }
  double left = iv_len(&rest);
  if (exact || (!bg && left > BT_SOLID_GAP * range)) {
    for (int k = 0; k < rest.n; k++)
      if (!iv_insert(&redo, rest.a[k], rest.b[k]))
        return 0;
  } else if (bg) {
    for (int k = 0; k < rest.n; k++) {
      rt_ray_t r;
      rt_rgb_t w;
      const sd_rec_t *qb = &T->rec[cand[bg - 1]];
      double um = 0.5 * (rest.a[k] + rest.b[k]);
      if (weight_held(qb, p))
        w = weight_at(T, qb, p, um);
      else if (!bt__exact_path_at(T, &qb->path, p, um - uc, &r, &w)) {
        if (!iv_insert(&redo, rest.a[k], rest.b[k]))
          return 0;
        continue;
      }
      *light = rt_rgb_add(
          *light, rt_rgb_mul(w, rt_rgb_mul(rt_wave_weight(&T->plan->wave, rest.a[k], rest.b[k]),
                                           T->s->background)));
    }
  }
  if (redo.n == 0)
    return 1;
  bm_path_t bp = *pre;
  bp.step[bp.n++] = *last;
  for (int k = 0; k < redo.n; k++)
    if (!remainder_exact(T, &bp, p, redo.a[k], redo.b[k], BT_SOLID_HALVINGS, light))
      return 0;
  return 1;
}

/* 1 when piece q lies below a child that one of the candidates cand[0 .. nc-1] found dark over
 * its box (not visited: q, a piece of another tile's record, shows nothing there). */
static int dark_above(const tile_t *T, const int *cand, int nc, const sd_rec_t *q) {
  for (int e = 0; e < nc; e++) {
    const sd_rec_t *a = &T->rec[cand[e]];
    for (int k = 0; k < a->nkid; k++)
      if (a->kdark[k] && below(&q->path, &a->path, &a->kid[k]))
        return 1;
  }
  return 0;
}

/* The light of a group's solids at point p (entry E: its path and its refraction): 0, with *light
 * undefined, when a check fails there. */
static int solid_point(tile_t *T, const sd_group_t *G, const sd_entry_t *E, const double p[2],
                       rt_rgb_t *out) {
  int cand[BT_SOLID_CAND], state[BT_SOLID_CAND], nc = 0, level[BT_SOLID_CAND];
  uint64_t ckey[BT_SOLID_CAND], phash[BT_SOLID_CAND];
  int gx = (int)floor((p[0] - G->gx0) / G->gcell), gy = (int)floor((p[1] - G->gy0) / G->gcell);
  if (gx < 0 || gy < 0 || gx >= G->gw || gy >= G->gh)
    return 0;
  int cell = gy * G->gw + gx;
  double best[BT_SOLID_CAND];
  int holds[BT_SOLID_CAND];
  for (int e = G->start[cell]; e < G->start[cell + 1]; e++) {
    int k = G->list[e];
    const sd_rec_t *q = &T->rec[k];
    if (p[0] < q->box[0] || p[0] > q->box[1] || p[1] < q->box[2] || p[1] > q->box[3])
      continue;
    /* pieces of one key (divisions, tiles) model p best from the one whose region's box holds
     * it, or else from the nearest */
    double dx = p[0] - q->c[0], dy = p[1] - q->c[1], d = dx * dx + dy * dy;
    int held = p[0] >= q->rbox[0] && p[0] <= q->rbox[1] && p[1] >= q->rbox[2] && p[1] <= q->rbox[3];
    /* the cell's list is in the order of the records' keys (grid_compact()), so candidates of
     * q's key are the last ones */
    int at = -1, run = nc;
    while (run > 0 && ckey[run - 1] == q->key)
      run--;
    for (int c = run; c < nc && at < 0; c++)
      if (same_key(&T->rec[cand[c]], q))
        at = c;
    if (at < 0) {
      if (nc == BT_SOLID_CAND)
        return 0;
      best[nc] = d;
      holds[nc] = held;
      ckey[nc] = q->key;
      cand[nc++] = k;
    } else if (held > holds[at] || (held == holds[at] && d < best[at])) {
      best[at] = d;
      holds[at] = held;
      cand[at] = k;
    }
  }
  sd_iv_t iv[BT_SOLID_CAND];
  int dropped[BT_SOLID_CAND], nd = 0, deepest = 0;
  for (int c = 0; c < nc; c++) {
    const sd_rec_t *q = &T->rec[cand[c]];
    iv[c].n = 0;
    state[c] = 0;
    level[c] = q->path.n;
    deepest = level[c] > deepest ? level[c] : deepest;
    phash[c] = steps_hash(SD_FNV_BASIS, q->path.step, q->path.n);
    if (!q->ok || (q->face >= 0 && !solid_intervals(T, q, p, &iv[c])))
      state[c] = -1; /* what it would draw is traced exactly with its beam's rest */
  }
  for (int c = 0; c < nc; c++)
    if (state[c] < 0)
      dropped[nd++] = c;
  for (int c = 0; c < nc && nd > 0; c++) /* what lies below a dropped piece is traced with it */
    for (int e = 0; e < nd && state[c] >= 0; e++)
      if (ancestor_of(&T->rec[cand[dropped[e]]], &T->rec[cand[c]]))
        state[c] = -1;
  rt_rgb_t light = rt_rgb(0, 0, 0);
  sd_iv_t whole = {1, {T->u[0]}, {T->u[BT_SOLID_SEGS]}};
  if (!solid_beam(T, p, &E->path, &E->st, &whole, cand, phash, iv, state, nc, &light))
    return 0;
  for (int l = T->sdepth + 1; l <= deepest; l++) /* parents first: what they show */
    for (int c = 0; c < nc; c++) {
      if (level[c] != l || state[c] <= 0 || iv[c].n == 0)
        continue;
      const sd_rec_t *q = &T->rec[cand[c]];
      if (q->face < 0)
        continue;
      for (int k = 0; k < q->nkid; k++) {
        if (q->kdark[k])
          continue; /* p lies in q's box (a candidate): nothing below shows (dark_above()) */
        if (!solid_beam(T, p, &q->path, &q->kid[k], &iv[c], cand, phash, iv, state, nc, &light))
          return 0;
      }
    }
  for (int c = 0; c < nc; c++) /* a piece no beam claimed: outside its parent's solid */
    if (state[c] == 0 && T->rec[cand[c]].face >= 0 && iv[c].n > 0 &&
        !dark_above(T, cand, nc, &T->rec[cand[c]]))
      return 0;
  *out = light;
  return 1;
}

/* The light refracted into the glass at point p of the entry (path's face g), traced exactly by
 * spectral pencils. */
static rt_rgb_t solid_exact(tile_t *T, const bm_path_t *path, int g, const double p[2]) {
  rt_ray_t ray;
  rt_rgb_t w;
  rt_surface_t sf;
  rt_child_t mirror;
  int nm;
  T->st.solid_exact++;
  if (!bt__exact_path(T, path, p, &ray, &w) || !bt__face_surface(T, &T->b->face[g], &ray, &sf))
    return rt_rgb(0, 0, 0);
  T->ex.node = -1;
  return rt_rgb_mul(w, rt_shade_spectral(T->s, T->plan, &sf, &ray, path->n, &T->tr, &mirror, &nm));
}

static int same_entry(const sd_entry_t *a, const sd_entry_t *b);

/* 1 when entry E's group is known (from another entry, in any tile) to be too fine for solids. */
static int fine_known(const tile_t *T, const sd_entry_t *E) {
  int known = 0;
  if (!T->fine)
    return 0;
#pragma omp critical(bt_solid_fine)
  for (int k = 0; k < T->fine->n && !known; k++)
    known = same_entry(&T->fine->ent[k], E);
  return known;
}

/* Entry E's group is too fine for solids: known to every later entry (where the list cannot grow,
 * later entries record their subtrees and find it out themselves). */
static void fine_add(const tile_t *T, const sd_entry_t *E) {
  if (!T->fine)
    return;
#pragma omp critical(bt_solid_fine)
  {
    sd_fine_t *F = T->fine;
    if (grow((void **)&F->ent, &F->cap, F->n + 1, sizeof *F->ent))
      F->ent[F->n++] = *E;
  }
}

/* Region r along path meets face g, where its rays' refraction st enters dispersive glass: the
 * subtree below recorded as dispersion image solids (or, --wavelengths pencils, not at all), and
 * r's cell shares as points that bt_render() draws from every tile's solids of the same entry
 * once all tiles are done: a solid's light crosses tile edges. */
void bt__solid(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int g, const bm_step_t *st,
               const rt_surface_t *sc, int splits, int level) {
  T->st.solids++;
  if (T->oom || !spend(T, (long long)sizeof *T->ent))
    return;
  if (!grow((void **)&T->ent, &T->capent, T->nent + 1, sizeof *T->ent)) {
    T->oom = 1;
    return;
  }
  int e = T->nent++;
  sd_entry_t *E = &T->ent[e];
  E->path = *path;
  E->g = g;
  E->st = *st;
  E->glass = sc->mat;
  E->bad = 0;
  E->first = T->nrec;
  E->box[0] = E->box[2] = INFINITY;
  E->box[1] = E->box[3] = -INFINITY;
  for (int k = 0; k < r->n; k++)
    for (int a = 0; a < 2; a++) {
      E->box[2 * a] = fmin(E->box[2 * a], r->v[k][a]);
      E->box[2 * a + 1] = fmax(E->box[2 * a + 1], r->v[k][a]);
    }
  int i0, i1, j0, j1, first = T->npt;
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      double x0 = T->a0 + (T->cx0 + i) * T->cell, y0 = T->b0 + (T->cy0 + j) * T->cell, area, p[2];
      if (!bt__clip_box(r, x0, x0 + T->cell, y0, y0 + T->cell, &area, p))
        continue;
      if (!spend(T, (long long)(sizeof *T->pt + sizeof(rt_rgb_t)))) /* and its light */
        return;
      if (!grow((void **)&T->pt, &T->cappt, T->npt + 1, sizeof *T->pt)) {
        T->oom = 1;
        return;
      }
      T->pt[T->npt++] =
          (sd_pt_t){e, T->cx0 + i, T->cy0 + j, area / (T->cell * T->cell), {p[0], p[1]}};
    }
  if (T->o->wavelengths == 2)
    return;
  if (fine_known(T, E)) { /* its points are traced with its group's */
    E->bad = 2;
    T->st.solid_skipped++;
    return;
  }
  /* the subtree, recorded: at most a record a point (and a few), or its pieces are too small
   * against the cells for solids to pay, and its points are traced (as its group's) */
  bm_path_t next = *path;
  next.step[next.n++] = *st;
  int oom = T->oom, nmod = T->nmod;
  T->oom = 0;
  T->collect = 1;
  T->climit = T->npt - first + BT_SOLID_FEW;
  T->sdepth = path->n;
  T->sglass = sc->mat;
  T->sentry = e;
  bt__beam(T, r, &next, splits, NULL, 0, level + 1);
  T->collect = 0;
  E = &T->ent[e];
  E->bad = T->oom;
  T->oom |= oom;
  if (T->climit <= 0) {
    E->bad = 2;
    fine_add(T, E);
    spend(T, -(long long)((size_t)(T->nrec - E->first) * sizeof *T->rec +
                          (size_t)(T->nmod - nmod) * sizeof *T->smod));
    T->nrec = E->first;
    T->nmod = nmod;
    return;
  }
  double reach = 0.0;
  for (int k = E->first; k < T->nrec; k++)
    reach = fmax(reach, solid_prepare(T, &T->rec[k]));
  for (int k = E->first; k < T->nrec; k++) /* a solid not traced: as far as the others reach */
    if (T->rec[k].box[0] > T->rec[k].box[1]) {
      sd_rec_t *q = &T->rec[k];
      double lo[2], hi[2];
      poly_box(&q->region, lo, hi);
      q->box[0] = lo[0] - reach;
      q->box[1] = hi[0] + reach;
      q->box[2] = lo[1] - reach;
      q->box[3] = hi[1] + reach;
    }
}

void bt__store_free(sd_store_t *a) {
  for (int k = 0; k < a->ngrp; k++) {
    free(a->grp[k].start);
    free(a->grp[k].list);
  }
  free(a->grp);
  free(a->rec);
  free(a->mod);
  free(a->ent);
  free(a->pt);
  free(a->light);
}

/* Append thread T's solids to a (indices shifted). 0 when out of memory. */
static int merge(sd_store_t *a, const tile_t *T) {
  if (!grow((void **)&a->rec, &a->caprec, a->nrec + T->nrec, sizeof *a->rec) ||
      !grow((void **)&a->mod, &a->capmod, a->nmod + T->nmod, sizeof *a->mod) ||
      !grow((void **)&a->ent, &a->capent, a->nent + T->nent, sizeof *a->ent) ||
      !grow((void **)&a->pt, &a->cappt, a->npt + T->npt, sizeof *a->pt))
    return 0;
  for (int k = 0; k < T->nrec; k++) {
    sd_rec_t *q = &a->rec[a->nrec + k];
    *q = T->rec[k];
    q->model += a->nmod;
    q->entry += a->nent;
  }
  if (T->nmod)
    memcpy(a->mod + a->nmod, T->smod, (size_t)T->nmod * sizeof *a->mod);
  for (int k = 0; k < T->nent; k++) {
    a->ent[a->nent + k] = T->ent[k];
    a->ent[a->nent + k].first += a->nrec;
  }
  for (int k = 0; k < T->npt; k++) {
    a->pt[a->npt + k] = T->pt[k];
    a->pt[a->npt + k].entry += a->nent;
  }
  a->nrec += T->nrec;
  a->nmod += T->nmod;
  a->nent += T->nent;
  a->npt += T->npt;
  return 1;
}

/* 1 when entries a and b enter the glass along one path at one face. */
static int same_entry(const sd_entry_t *a, const sd_entry_t *b) {
  return a->g == b->g && a->st.event == b->st.event && same_steps(&a->path, &b->path);
}

typedef struct {
  uint64_t key;
  int rec;
} sd_keyed_t;

static int by_key(const void *a, const void *b) {
  const sd_keyed_t *x = a, *y = b;
  return x->key < y->key ? -1 : x->key > y->key ? 1 : x->rec - y->rec;
}

/* Each cell of G's grid (its list in the order of the records' keys, then indices) keeps, of the
 * records of one key (pieces of one path and face that divisions and tiles cut apart), those whose
 * region's box meets the cell, or else the one whose centroid is nearest the cell's centre: the
 * ones solid_point() may pick there. 0 when out of memory. */
static int grid_compact(const sd_store_t *a, sd_group_t *G) {
  int cells = G->gw * G->gh, most = 0, out = 0;
  for (int c = 0; c < cells; c++)
    most = G->start[c + 1] - G->start[c] > most ? G->start[c + 1] - G->start[c] : most;
  sd_keyed_t *t = malloc((size_t)(most > 0 ? most : 1) * sizeof *t);
  if (!t)
    return 0;
  for (int c = 0; c < cells; c++) {
    int n = G->start[c + 1] - G->start[c];
    for (int k = 0; k < n; k++) {
      int r = G->list[G->start[c] + k];
      t[k] = (sd_keyed_t){a->rec[r].key, r};
    }
    /* in the order of their keys and indices already (groups_make()) */
    double x0 = G->gx0 + (c % G->gw) * G->gcell, y0 = G->gy0 + (c / G->gw) * G->gcell;
    double x1 = x0 + G->gcell, y1 = y0 + G->gcell, cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    G->start[c] = out;
    for (int k = 0; k < n;) {
      int e = k, meets = 0, near = -1;
      double best = INFINITY;
      while (e < n && t[e].key == t[k].key)
        e++;
      for (int m = k; m < e; m++) {
        const sd_rec_t *q = &a->rec[t[m].rec];
        if (q->rbox[0] <= x1 && q->rbox[1] >= x0 && q->rbox[2] <= y1 && q->rbox[3] >= y0) {
          G->list[out++] = t[m].rec;
          meets = 1;
        }
        double d = hypot(q->c[0] - cx, q->c[1] - cy);
        if (d < best) {
          best = d;
          near = t[m].rec;
        }
      }
      if (!meets)
        G->list[out++] = near;
      k = e;
    }
  }
  G->start[cells] = out;
  free(t);
  return 1;
}

/* The entries' groups and each group's grid of records (cells of 4 pixels). 0 when out of
 * memory. */
static int groups_make(sd_store_t *a, double pixel, bt_stats_t *st) {
  if (a->nent == 0)
    return 1;
  a->grp = calloc((size_t)a->nent, sizeof *a->grp);
  if (!a->grp)
    return 0;
  for (int e = 0; e < a->nent; e++) {
    int g = 0;
    while (g < a->ngrp && !same_entry(&a->ent[a->grp[g].entry], &a->ent[e]))
      g++;
    if (g == a->ngrp)
      a->grp[a->ngrp++].entry = e;
    a->ent[e].group = g;
  }
  /* a group whose subtree was too fine to record in one tile is traced in every tile: a solid
   * sweeps across tile edges, so its neighbours' records would be missing */
  for (int e = 0; e < a->nent; e++)
    if (a->ent[e].bad)
      for (int f = 0; f < a->nent; f++)
        if (a->ent[f].group == a->ent[e].group && !a->ent[f].bad)
          a->ent[f].bad = 3;
  /* the counts of what is drawn, whatever the order in which the threads met the entries */
  for (int e = 0; e < a->nent; e++)
    st->solid_fine += a->ent[e].bad != 0;
  for (int k = 0; k < a->nrec; k++) {
    const sd_rec_t *q = &a->rec[k];
    if (a->ent[q->entry].bad)
      continue;
    st->solid_records++;
    st->solid_failed += q->failed;
    st->solid_wexact += q->ok && q->face != BT_REC_EXACT && !q->wok;
    st->solid_dark += (uint64_t)(q->kdark[0] + q->kdark[1]);
  }
  for (int g = 0; g < a->ngrp; g++) {
    sd_group_t *G = &a->grp[g];
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int e = 0; e < a->nent; e++) /* the points lie in its entries' boxes */
      if (a->ent[e].group == g)
        for (int x = 0; x < 2; x++) {
          lo[x] = fmin(lo[x], a->ent[e].box[2 * x]);
          hi[x] = fmax(hi[x], a->ent[e].box[2 * x + 1]);
        }
    G->gcell = 4.0 * pixel;
    G->gx0 = lo[0];
    G->gy0 = lo[1];
    G->gw = 1 + (int)((hi[0] - lo[0]) / G->gcell);
    G->gh = 1 + (int)((hi[1] - lo[1]) / G->gcell);
    G->start = calloc((size_t)G->gw * G->gh + 1, sizeof *G->start);
    if (!G->start)
      return 0;
  }
  /* twice over the records in the order of their keys (then their indices), so that each cell's
   * list comes out in that order: count per cell, then fill */
  sd_keyed_t *order = malloc((size_t)(a->nrec > 0 ? a->nrec : 1) * sizeof *order);
  if (!order)
    return 0;
  for (int k = 0; k < a->nrec; k++)
    order[k] = (sd_keyed_t){a->rec[k].key, k};
  qsort(order, (size_t)a->nrec, sizeof *order, by_key);
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < a->nrec; i++) {
      int k = order[i].rec;
      const sd_rec_t *q = &a->rec[k];
      sd_group_t *G = &a->grp[a->ent[q->entry].group];
      if (!(q->box[0] <= q->box[1]) || a->ent[q->entry].bad)
        continue; /* no solid, or its group's points are traced: never a candidate */
      int x0 = (int)fmax(0.0, floor((q->box[0] - G->gx0) / G->gcell));
      int x1 = (int)fmin(G->gw - 1.0, floor((q->box[1] - G->gx0) / G->gcell));
      int y0 = (int)fmax(0.0, floor((q->box[2] - G->gy0) / G->gcell));
      int y1 = (int)fmin(G->gh - 1.0, floor((q->box[3] - G->gy0) / G->gcell));
      for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
          int c = y * G->gw + x;
          if (pass == 0)
            G->start[c + 1]++;
          else
            G->list[G->start[c]++] = k;
        }
    }
    for (int g = 0; g < a->ngrp; g++) {
      sd_group_t *G = &a->grp[g];
      int cells = G->gw * G->gh;
      if (pass == 0) {
        for (int c = 0; c < cells; c++)
          G->start[c + 1] += G->start[c];
        G->list = malloc((size_t)(G->start[cells] > 0 ? G->start[cells] : 1) * sizeof *G->list);
        if (!G->list) {
          free(order);
          return 0;
        }
      } else { /* the fill moved each start to the next cell's: back */
        for (int c = cells; c > 0; c--)
          G->start[c] = G->start[c - 1];
        G->start[0] = 0;
      }
    }
  }
  free(order);
  for (int g = 0; g < a->ngrp; g++)
    if (!grid_compact(a, &a->grp[g]))
      return 0;
  return 1;
}

/* Points by cell, then by point. */
static int by_cell(const void *a, const void *b) {
  const sd_pt_t *x = a, *y = b;
  if (x->cy != y->cy)
    return x->cy < y->cy ? -1 : 1;
  if (x->cx != y->cx)
    return x->cx < y->cx ? -1 : 1;
  if (x->p[0] != y->p[0])
    return x->p[0] < y->p[0] ? -1 : 1;
  return x->p[1] < y->p[1] ? -1 : x->p[1] > y->p[1] ? 1 : 0;
}

int bt__solids_draw(tile_t *T, sd_store_t *all, rt_image_t *img, int W, int H, int s) {
  int ok = !T->oom;
#pragma omp critical(bt_solids)
  if (ok)
    ok = merge(all, T);
  free(T->rec);
  free(T->smod);
  free(T->ent);
  free(T->pt);
  T->rec = NULL;
  T->smod = NULL;
  T->ent = NULL;
  T->pt = NULL;
  if (!ok) {
#pragma omp atomic write
    all->failed = 1;
  }
#pragma omp barrier
#pragma omp single
  {
    if (!all->failed && !groups_make(all, T->pixel, &T->st))
      all->failed = 1;
  }
#pragma omp single
  {
    if (!all->failed &&
        !(all->light = malloc((size_t)(all->npt > 0 ? all->npt : 1) * sizeof *all->light)))
      all->failed = 1;
  }
  int stop;
#pragma omp atomic read
  stop = all->failed;
  ok = !stop;
  T->rec = all->rec;
  T->smod = all->mod;
#pragma omp for schedule(dynamic, 64)
  for (int k = 0; k < all->npt; k++) {
    if (!ok)
      continue;
    const sd_pt_t *q = &all->pt[k];
    const sd_entry_t *E = &all->ent[q->entry];
    T->sdepth = E->path.n;
    T->sglass = E->glass;
    rt_rgb_t L;
    if (!E->bad && T->o->wavelengths != 2 && solid_point(T, &all->grp[E->group], E, q->p, &L))
      T->st.solid_points++;
    else
      L = solid_exact(T, &E->path, E->g, q->p);
    all->light[k] = rt_rgb_scale(L, q->frac / (s * s));
  }
  T->rec = NULL;
  T->smod = NULL;
  /* into the image in an order of their own (cell, then point), so that the sums do not depend on
   * the threads */
#pragma omp single
  if (ok) {
    /* the points sorted with their lights: sd_pt_t's entry field carries the point's index */
    size_t cw = (size_t)W * s, cells = cw * (size_t)H * s;
    sd_pt_t *order = malloc((size_t)(all->npt > 0 ? all->npt : 1) * sizeof *order);
    /* counted by cell where the cells are not many more than the points (the counts then take
     * less memory than the points do), sorted otherwise: the same order either way */
    size_t *start = cells <= 4 * (size_t)all->npt ? calloc(cells + 1, sizeof *start) : NULL;
    if (!order) {
      all->failed = 1;
    } else if (!start) {
      for (int k = 0; k < all->npt; k++) {
        order[k] = all->pt[k];
        order[k].entry = k;
      }
      qsort(order, (size_t)all->npt, sizeof *order, by_cell);
    } else {
      for (int k = 0; k < all->npt; k++)
        start[(size_t)all->pt[k].cy * cw + (size_t)all->pt[k].cx + 1]++;
      for (size_t c = 0; c < cells; c++)
        start[c + 1] += start[c];
      for (int k = 0; k < all->npt; k++) {
        size_t at = start[(size_t)all->pt[k].cy * cw + (size_t)all->pt[k].cx]++;
        order[at] = all->pt[k];
        order[at].entry = k;
      }
      for (int k = 1; k < all->npt; k++) /* in order but within cells (by_cell() orders cells) */
        for (int at = k; at > 0 && by_cell(&order[at - 1], &order[at]) > 0; at--) {
          sd_pt_t t = order[at];
          order[at] = order[at - 1];
          order[at - 1] = t;
        }
    }
    if (order) {
      for (int k = 0; k < all->npt;) {
        size_t px = (size_t)(order[k].cy / s) * W + (size_t)(order[k].cx / s);
        rt_rgb_t sum = rt_rgb(0, 0, 0);
        for (; k < all->npt && (size_t)(order[k].cy / s) * W + (size_t)(order[k].cx / s) == px; k++)
          sum = rt_rgb_add(sum, all->light[order[k].entry]);
        img->ch[RT_CH_R][px] = (float)(img->ch[RT_CH_R][px] + sum.r);
        img->ch[RT_CH_G][px] = (float)(img->ch[RT_CH_G][px] + sum.g);
        img->ch[RT_CH_B][px] = (float)(img->ch[RT_CH_B][px] + sum.b);
      }
    }
    free(order);
    free(start);
  }
  (void)H;
#pragma omp atomic read
  stop = all->failed;
  return ok && !stop;
}
