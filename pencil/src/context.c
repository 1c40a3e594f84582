/* context.c -- the per-thread state of the pencil renderer (internal.h, pt_ctx_t): each part's
 * buffers, allocated once before the screen loop so that no ray allocates (paper section 4.1:
 * every domain reuses them). An alloc that fails leaves what it did allocate for its free; a
 * free releases everything and leaves the part empty, so freeing twice is harmless. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* Lattice memo: a 5 x 5 domain at 49 spp needs at most 33 x 33 points; its node records hold at
 * least one whole tree. */
#define PT_MEMO_POINTS 2048
#define PT_MEMO_BYTES ((size_t)8 << 20)

int pt__trees_alloc(pt_trees_t *t, int cap) {
  t->axial = rt_tree_make(malloc((size_t)cap * sizeof(rt_tree_node_t)), cap);
  t->probe = rt_tree_make(malloc((size_t)cap * sizeof(rt_tree_node_t)), cap);
  return t->axial.node && t->probe.node;
}

void pt__trees_free(pt_trees_t *t) {
  free(t->axial.node);
  free(t->probe.node);
  memset(t, 0, sizeof *t);
}

int pt__subtrees_alloc(pt_subtrees_t *t, int cap) {
  t->tree = rt_tree_make(malloc((size_t)PT_SUB_TREES * (size_t)cap * sizeof(rt_tree_node_t)),
                         PT_SUB_TREES * cap);
  t->root = malloc((size_t)cap * sizeof *t->root);
  t->from = malloc((size_t)cap * sizeof *t->from);
  t->exact_node = malloc((size_t)cap * sizeof *t->exact_node);
  t->n = 0;
  return t->tree.node && t->root && t->from && t->exact_node;
}

void pt__subtrees_free(pt_subtrees_t *t) {
  free(t->tree.node);
  free(t->root);
  free(t->from);
  free(t->exact_node);
  memset(t, 0, sizeof *t);
}

int pt__corners_alloc(pt_corners_t *c, int cap, int n) {
  size_t side = (size_t)n + 1, corners = side * side;
  c->tree = calloc(corners, sizeof *c->tree);
  c->nodes = malloc(corners * (size_t)cap * sizeof *c->nodes);
  c->map = malloc(4 * (size_t)cap * sizeof *c->map);
  c->agree = malloc((size_t)cap);
  c->light = malloc((size_t)cap * sizeof *c->light);
  if (!c->tree || !c->nodes || !c->map || !c->agree || !c->light)
    return 0;
  for (size_t i = 0; i < corners; i++)
    c->tree[i] = (pt_ctree_t){c->nodes + i * (size_t)cap, cap, -1, 0};
  return 1;
}

void pt__corners_free(pt_corners_t *c) {
  free(c->tree);
  free(c->nodes);
  free(c->map);
  free(c->agree);
  free(c->light);
  memset(c, 0, sizeof *c);
}

int pt__paths_alloc(pt_paths_t *p, int cap) {
  p->node = malloc((size_t)cap * sizeof *p->node);
  p->n = 0;
  return p->node != NULL;
}

void pt__paths_free(pt_paths_t *p) {
  free(p->node);
  p->node = NULL;
  p->n = 0;
}

/* The lattice cell plan's per-node buffers (the flags zeroed). */
static int plan_alloc(pt_lattice_plan_t *p, int cap) {
  p->shaded = malloc((size_t)cap * sizeof *p->shaded);
  p->shaded_direct = malloc((size_t)cap);
  p->shaded_exact = malloc((size_t)cap);
  p->leaves = malloc((size_t)cap * sizeof *p->leaves);
  p->linear = malloc((size_t)cap * sizeof *p->linear);
  p->exact_subtree = calloc((size_t)cap, 1);
  p->traced = calloc((size_t)cap, 1);
  p->biquadratic = calloc((size_t)cap, 1);
  p->faint = calloc((size_t)cap, 1);
  return p->shaded && p->shaded_direct && p->shaded_exact && p->leaves && p->linear &&
         p->exact_subtree && p->traced && p->biquadratic && p->faint;
}

static void plan_free(pt_lattice_plan_t *p) {
  free(p->shaded);
  free(p->shaded_direct);
  free(p->shaded_exact);
  free(p->leaves);
  free(p->linear);
  free(p->exact_subtree);
  free(p->traced);
  free(p->biquadratic);
  free(p->faint);
  memset(p, 0, sizeof *p);
}

/* The memo: PT_MEMO_BYTES of node records (at least one whole tree), a point taking as many as
 * its domain's tree has nodes, for PT_MEMO_POINTS points at most. */
static int memo_alloc(pt_lattice_memo_t *M, int cap) {
  size_t mcap = PT_MEMO_POINTS, entries = PT_MEMO_BYTES / sizeof(pt_geom_t);
  if (entries < (size_t)cap)
    entries = (size_t)cap;
  size_t nslot = 1;
  while (nslot < 2 * mcap)
    nslot *= 2;
  *M = (pt_lattice_memo_t){.entries = entries, .maxpts = (int)mcap, .nslot = (int)nslot};
  M->g = malloc(entries * sizeof(pt_geom_t));
  M->xy = malloc(2 * mcap * sizeof *M->xy);
  M->xi2 = malloc(mcap * sizeof *M->xi2);
  M->ok = malloc(mcap);
  M->slot = malloc(nslot * sizeof *M->slot);
  M->gen = calloc(nslot, sizeof *M->gen);
  return M->g && M->xy && M->xi2 && M->ok && M->slot && M->gen;
}

static void memo_free(pt_lattice_memo_t *M) {
  free(M->g);
  free(M->xy);
  free(M->xi2);
  free(M->ok);
  free(M->slot);
  free(M->gen);
  memset(M, 0, sizeof *M);
}

int pt__lattice_alloc(pt_lattice_t *l, int cap, int n) {
  l->root = malloc(9 * (size_t)cap * sizeof *l->root);
  l->refine = malloc((size_t)PT_LATTICE_LEVELS * 5 * (size_t)cap * sizeof *l->refine);
  l->pixels = malloc((size_t)n * (size_t)n * sizeof *l->pixels);
  int plan = plan_alloc(&l->plan, cap), memo = memo_alloc(&l->memo, cap);
  return l->root && l->refine && l->pixels && plan && memo;
}

void pt__lattice_free(pt_lattice_t *l) {
  free(l->root);
  free(l->refine);
  free(l->pixels);
  plan_free(&l->plan);
  memo_free(&l->memo);
  memset(l, 0, sizeof *l);
}

int pt__sample_alloc(pt_sample_t *x, int cap) {
  x->geom = calloc((size_t)cap, sizeof *x->geom);
  x->exact = calloc((size_t)cap, sizeof *x->exact);
  x->stamp = 0;
  return x->geom && x->exact;
}

void pt__sample_free(pt_sample_t *x) {
  free(x->geom);
  free(x->exact);
  memset(x, 0, sizeof *x);
}

int pt__ctx_alloc(pt_ctx_t *C, int cap, int n) {
  C->cap = cap;
  int ok = pt__trees_alloc(&C->trees, cap);
  ok &= pt__subtrees_alloc(&C->sub, cap);
  ok &= pt__corners_alloc(&C->corners, cap, n);
  ok &= pt__paths_alloc(&C->paths, cap);
  ok &= pt__lattice_alloc(&C->lattice, cap, n);
  ok &= pt__sample_alloc(&C->sample, cap);
  return ok;
}

void pt__ctx_free(pt_ctx_t *C) {
  pt__trees_free(&C->trees);
  pt__subtrees_free(&C->sub);
  pt__corners_free(&C->corners);
  pt__paths_free(&C->paths);
  pt__lattice_free(&C->lattice);
  pt__sample_free(&C->sample);
}
