/* interp_memo.c -- the lattice points of one domain's lattice cells (paper section 4.1 (2): the
 * rays the interpolation starts from are traced by the domain's system matrices, Eqs. 1-2 as in
 * section 4.1 (1)), kept by position: neighbouring lattice cells share corners and edge
 * midpoints, and a point depends only on its position and the domain's paths, so it is traced
 * once per domain. */
#include <string.h>

#include "interp.h"

/* Slot of position (x, y) in the memo's hash table: its own, or the empty one where it would go. */
static int memo_slot(const pt_lattice_memo_t *M, double x, double y) {
  uint64_t a, b;
  memcpy(&a, &x, sizeof a);
  memcpy(&b, &y, sizeof b);
  uint64_t h = (a ^ (b * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
  int mask = M->nslot - 1, i = (int)((h >> 32) & (uint64_t)mask);
  for (;; i = (i + 1) & mask) { /* never full: nslot >= 2 cap */
    if (M->gen[i] != M->now)
      return i;
    const double *p = &M->xy[2 * M->slot[i]];
    if (p[0] == x && p[1] == y)
      return i;
  }
}

/* The lattice point at (x, y) traced through the paths: the domain's memo holds it when a
 * neighbouring lattice cell traced it already (the evaluation depends on nothing but the position
 * and the domain's paths, so it is the same point); otherwise it is traced into the memo, or into g
 * (cap nodes) when the memo is full. record_shadow: the point is the domain's axial ray, whose
 * evaluation also records the domain's shadow transmittances (pt__record_shadows). */
lattice_point_t pt__lattice_point(pt_ctx_t *C, double x, double y, pt_geom_t *g,
                                  int record_shadow) {
  pt_lattice_memo_t *M = &C->lattice.memo;
  int s = memo_slot(M, x, y);
  if (M->gen[s] == M->now && C->opt->memo) {
    int i = M->slot[s];
    C->st.lattice_reused++;
    return (lattice_point_t){M->g + (size_t)i * (size_t)M->stride, M->xi2[i], M->ok[i]};
  }
  int i = M->n < M->cap ? M->n++ : -1;
  if (i >= 0)
    g = M->g + (size_t)i * (size_t)M->stride;
  pt_eval_t E = {.C = C,
                 .mode = PT_EV_MATRIX,
                 .shade = 1,
                 .geom = g,
                 .lattice = 1,
                 .record_shadow = record_shadow};
  pt__xi_of(C, &E, x, y);
  pt__eval(&E);
  C->st.lattice_points++;
  lattice_point_t pt = {g, E.xi[0] * E.xi[0] + E.xi[1] * E.xi[1], !E.fallback};
  if (i >= 0) {
    M->xy[2 * i] = x;
    M->xy[2 * i + 1] = y;
    M->xi2[i] = pt.xi2;
    M->ok[i] = (uint8_t)pt.ok;
    M->slot[s] = i;
    M->gen[s] = M->now;
  }
  return pt;
}

/* Start the memo for a new domain (its points depend on the domain's paths) whose trees have nnode
 * nodes: a point's records are stored contiguously, nnode of them, so that the grids
 * pt__make_plan() reads are compact (the tree's capacity as the stride would spread a small
 * tree's records over many times their size: docs/tuning.md). */
void pt__memo_reset(pt_lattice_memo_t *M, int nnode) {
  M->n = 0;
  M->stride = nnode > 0 ? nnode : 1;
  size_t room = M->entries / (size_t)M->stride;
  M->cap = room < (size_t)M->maxpts ? (int)room : M->maxpts;
  if (++M->now == 0) { /* wrapped: old generations could look current */
    memset(M->gen, 0, (size_t)M->nslot * sizeof *M->gen);
    M->now = 1;
  }
}

/* x as a float no greater (down) or no less than it. */
static float float_out(double x, int up) {
  float f = (float)x;
  if (up ? (double)f < x : (double)f > x)
    f = nextafterf(f, up ? INFINITY : -INFINITY);
  return f;
}

int pt__spec_put(pt_ctx_t *C, const rt_spectral_rec_t *rec, uint32_t *at) {
  pt_spec_table_t *T = &C->lattice.spec;
  if (T->n + (uint32_t)rec->nev > PT_SPEC_EVENTS)
    return 0;
  *at = T->n;
  for (int e = 0; e < rec->nev; e++, T->n++) {
    pt_spec_event_t *x = &T->ev[T->n];
    for (int a = 0; a < 6; a++) {
      x->box[a] = float_out(rec->from[e][a], a >= 3);
      x->box[6 + a] = float_out(rec->to[e][a], a >= 3);
    }
    for (int k = 0; k < RT_SPECTRAL_EVENT_PRIMS; k++)
      x->prim[k] = rec->prim[e][k];
  }
  return 1;
}
