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

/* Every buffer of a context comes through these, which count the bytes asked for on this thread
 * (pt__ctx_alloc() keeps the count in pt_ctx_t.bytes, so that tests hold pt_thread_bytes() to
 * it). */
static _Thread_local size_t taken;

static void *take(size_t bytes) {
  taken += bytes;
  return malloc(bytes);
}

static void *take0(size_t n, size_t size) {
  taken += n * size;
  return calloc(n, size);
}

int pt__trees_alloc(pt_trees_t *t, int cap, int probe_cap) {
  t->axial = rt_tree_make(take((size_t)cap * sizeof(rt_tree_node_t)), cap);
  t->probe = rt_tree_make(take((size_t)probe_cap * sizeof(rt_tree_node_t)), probe_cap);
  t->side = rt_tree_make(take((size_t)cap * sizeof(rt_tree_node_t)), cap);
  t->side_p = take(4 * (size_t)cap * sizeof *t->side_p);
  t->side_ok = take(4 * (size_t)cap);
  return t->axial.node && t->probe.node && t->side.node && t->side_p && t->side_ok;
}

void pt__trees_free(pt_trees_t *t) {
  free(t->axial.node);
  free(t->probe.node);
  free(t->side.node);
  free(t->side_p);
  free(t->side_ok);
  memset(t, 0, sizeof *t);
}

int pt__subtrees_alloc(pt_subtrees_t *t, int cap) {
  t->tree = rt_tree_make(take((size_t)PT_SUB_TREES * (size_t)cap * sizeof(rt_tree_node_t)),
                         PT_SUB_TREES * cap);
  t->root = take((size_t)cap * sizeof *t->root);
  t->from = take((size_t)cap * sizeof *t->from);
  t->exact_node = take((size_t)cap * sizeof *t->exact_node);
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
  c->tree = take0(corners, sizeof *c->tree);
  c->nodes = take(corners * (size_t)cap * sizeof *c->nodes);
  c->map = take(4 * (size_t)cap * sizeof *c->map);
  c->agree = take((size_t)cap);
  c->light = take((size_t)cap * sizeof *c->light);
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
  p->node = take((size_t)cap * sizeof *p->node);
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
  p->shaded = take((size_t)cap * sizeof *p->shaded);
  p->shaded_direct = take((size_t)cap);
  p->shaded_exact = take((size_t)cap);
  p->leaves = take((size_t)cap * sizeof *p->leaves);
  p->linear = take((size_t)cap * sizeof *p->linear);
  p->exact_subtree = take0((size_t)cap, 1);
  p->traced = take0((size_t)cap, 1);
  p->biquadratic = take0((size_t)cap, 1);
  p->faint = take0((size_t)cap, 1);
  p->spec_lin = take0((size_t)cap, 1);
  p->spec = take((size_t)cap * sizeof *p->spec);
  return p->shaded && p->shaded_direct && p->shaded_exact && p->leaves && p->linear &&
         p->exact_subtree && p->traced && p->biquadratic && p->faint && p->spec_lin && p->spec;
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
  free(p->spec_lin);
  free(p->spec);
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
  M->g = take(entries * sizeof(pt_geom_t));
  M->xy = take(2 * mcap * sizeof *M->xy);
  M->xi2 = take(mcap * sizeof *M->xi2);
  M->ok = take(mcap);
  M->slot = take(nslot * sizeof *M->slot);
  M->gen = take0(nslot, sizeof *M->gen);
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
  l->root = take(9 * (size_t)cap * sizeof *l->root);
  l->refine = take((size_t)PT_LATTICE_LEVELS * 5 * (size_t)cap * sizeof *l->refine);
  l->pixels = take((size_t)n * (size_t)n * sizeof *l->pixels);
  l->spec.ev = take((size_t)PT_SPEC_EVENTS * sizeof *l->spec.ev);
  l->spec_off = take0((size_t)cap, 1);
  int plan = plan_alloc(&l->plan, cap), memo = memo_alloc(&l->memo, cap);
  return l->root && l->refine && l->pixels && l->spec.ev && l->spec_off && plan && memo;
}

void pt__lattice_free(pt_lattice_t *l) {
  free(l->root);
  free(l->refine);
  free(l->pixels);
  free(l->spec.ev);
  free(l->spec_off);
  plan_free(&l->plan);
  memo_free(&l->memo);
  memset(l, 0, sizeof *l);
}

int pt__sample_alloc(pt_sample_t *x, int cap) {
  x->geom = take0((size_t)cap, sizeof *x->geom);
  x->exact = take0((size_t)cap, sizeof *x->exact);
  x->exact4 = take0((size_t)cap, sizeof *x->exact4);
  x->stamp = 0;
  x->group.stamp = 0; /* stamps start at 1: calloc's 0 is no group */
  return x->geom && x->exact && x->exact4;
}

void pt__sample_free(pt_sample_t *x) {
  free(x->geom);
  free(x->exact);
  free(x->exact4);
  memset(x, 0, sizeof *x);
}

int pt__ctx_alloc(pt_ctx_t *C, int tree_nodes, int n) {
  int cap = tree_nodes < PT_MAX_TREE_NODES ? tree_nodes : PT_MAX_TREE_NODES;
  size_t before = taken;
  C->cap = cap;
  int ok = pt__trees_alloc(&C->trees, cap, tree_nodes);
  ok &= pt__subtrees_alloc(&C->sub, cap);
  ok &= pt__corners_alloc(&C->corners, cap, n);
  ok &= pt__paths_alloc(&C->paths, cap);
  ok &= pt__lattice_alloc(&C->lattice, cap, n);
  ok &= pt__sample_alloc(&C->sample, cap);
  C->bytes = taken - before;
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

/* Every byte the allocs above take for one thread, term by term in their order (the test
 * test_pencil.c:thread_bytes_match_allocation holds the two in step). */
size_t pt_thread_bytes(int tree_nodes, int domain) {
  if (tree_nodes < 1 || domain < 1)
    return 0;
  pt_ctx_t *C = NULL; /* only in sizeof, which does not evaluate it */
  size_t cap = (size_t)(tree_nodes < PT_MAX_TREE_NODES ? tree_nodes : PT_MAX_TREE_NODES);
  size_t full = (size_t)tree_nodes, side = (size_t)domain + 1, corners = side * side;
  size_t node = sizeof(rt_tree_node_t), geom = sizeof(pt_geom_t);
  size_t b = (2 * cap + full) * node + 4 * cap * (sizeof *C->trees.side_p + 1); /* trees */
  b += PT_SUB_TREES * cap * node +
       cap * (sizeof *C->sub.root + sizeof *C->sub.from + sizeof *C->sub.exact_node); /* subtrees */
  b += corners * (sizeof *C->corners.tree + cap * sizeof *C->corners.nodes) +
       cap * (4 * sizeof *C->corners.map + 1 + sizeof *C->corners.light); /* corners */
  b += cap * sizeof *C->paths.node;                                       /* paths */
  b += (9 + (size_t)PT_LATTICE_LEVELS * 5) * cap * geom +
       (size_t)domain * (size_t)domain * sizeof *C->lattice.pixels; /* lattice grids, pixels */
  b += cap * (sizeof *C->lattice.plan.shaded + 2 + sizeof *C->lattice.plan.leaves +
              sizeof *C->lattice.plan.linear + sizeof *C->lattice.plan.spec + 6);
  b += (size_t)PT_SPEC_EVENTS * sizeof *C->lattice.spec.ev; /* spectral events */
  size_t entries = PT_MEMO_BYTES / geom, nslot = 1;
  if (entries < cap)
    entries = cap;
  while (nslot < 2 * (size_t)PT_MEMO_POINTS)
    nslot *= 2;
  b += entries * geom +
       PT_MEMO_POINTS * (2 * sizeof *C->lattice.memo.xy + sizeof *C->lattice.memo.xi2 + 1) +
       nslot * (sizeof *C->lattice.memo.slot + sizeof *C->lattice.memo.gen); /* memo */
  b += cap *
       (sizeof *C->sample.geom + sizeof *C->sample.exact + sizeof *C->sample.exact4); /* sample */
  return b;
}
