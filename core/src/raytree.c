/* raytree.c -- queries on recorded ray trees (textbook 9.1: the binary tree of rays of a
 * pixel; paper section 3: pencils are valid only while neighbouring rays meet the same
 * surfaces, so edges lie where the trees differ). */
#include "core/raytree.h"

#include <string.h>

int rt_tree_follow(const rt_tree_t *t, rt_ray_kind_t prefer) {
  int cur = t->n > 0 ? 0 : -1;
  while (cur >= 0) {
    if (t->node[cur].texel >= 0)
      return cur;
    int next = -1;
    for (int k = cur + 1; k < t->n; k++)
      if (t->node[k].parent == cur && (next < 0 || t->node[k].kind == (uint8_t)prefer))
        next = k;
    cur = next;
  }
  return -1;
}

static int same_node(const rt_tree_node_t *a, const rt_tree_node_t *b) {
  return a->parent == b->parent && a->kind == b->kind && a->flags == b->flags &&
         a->object == b->object && a->prim == b->prim && a->texel == b->texel && a->lit == b->lit &&
         a->blocked == b->blocked && a->through == b->through;
}

int rt_tree_same(const rt_tree_t *a, const rt_tree_t *b) {
  if (a->n != b->n || a->overflow || b->overflow)
    return 0;
  for (int k = 0; k < a->n; k++)
    if (!same_node(&a->node[k], &b->node[k]))
      return 0;
  return 1;
}
