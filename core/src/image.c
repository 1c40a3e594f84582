/* image.c -- the float image with RGB and the auxiliary accuracy channels (paper section 5,
 * Fig. 10: errors are distances between checkerboard points of the two tracers). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/image.h"

static const char *const channel_names[RT_CH_COUNT] = {
    "R", "G", "B", "Z", "id", "pathT.u", "pathT.v", "pathT.k", "pathR.u", "pathR.v", "pathR.k"};

const char *rt_channel_name(rt_channel_t c) {
  return (unsigned)c < RT_CH_COUNT ? channel_names[c] : "?";
}

rt_status_t rt_image_alloc(rt_image_t *img, int width, int height) {
  img->width = img->height = 0;
  img->spectral = NULL;
  for (int c = 0; c < RT_CH_COUNT; c++)
    img->ch[c] = NULL;
  if (width < 1 || height < 1 || (size_t)width > ((size_t)1 << 30) / (size_t)height)
    return RT_EINVAL;
  size_t n = (size_t)width * (size_t)height;
  for (int c = 0; c < RT_CH_COUNT; c++)
    if (!(img->ch[c] = calloc(n, sizeof(float)))) {
      rt_image_free(img);
      return RT_ENOMEM;
    }
  img->width = width;
  img->height = height;
  return RT_OK;
}

rt_status_t rt_image_want_spectral(rt_image_t *img) {
  if (!img->spectral &&
      !(img->spectral = calloc((size_t)img->width * (size_t)img->height, sizeof(float))))
    return RT_ENOMEM;
  return RT_OK;
}

void rt_image_free(rt_image_t *img) {
  for (int c = 0; c < RT_CH_COUNT; c++) {
    free(img->ch[c]);
    img->ch[c] = NULL;
  }
  free(img->spectral);
  img->spectral = NULL;
  img->width = img->height = 0;
}

/* Whether tree t refracts at dispersive glass where shading has children: the condition under
 * which shade.c's spectral() draws a white ray's spectrum (the first such node of a tree is met by
 * the white ray; nodes below it, where the fan records them, are its wavelengths). */
static int tree_disperses(const rt_scene_t *s, const rt_tree_t *t) {
  for (int i = 0; i < t->n; i++) {
    const rt_tree_node_t *n = &t->node[i];
    if (n->flags & (RT_NODE_MISS | RT_NODE_DEPTH_LIMIT))
      continue;
    const rt_material_t *m = rt_scene_material_at(s, n->prim, n->point, NULL);
    if (m->kt > 0.0 && px_index_disperses(&m->index))
      return 1;
  }
  return 0;
}

void rt_image_set_spectral(rt_image_t *img, const rt_scene_t *s, size_t k, const rt_tree_t *t) {
  if (img->spectral)
    img->spectral[k] = (float)tree_disperses(s, t);
}

void rt_image_set_aux(rt_image_t *img, const rt_scene_t *s, size_t k, const rt_tree_t *t) {
  const rt_tree_node_t *root = &t->node[0];
  rt_image_set_spectral(img, s, k, t);
  img->ch[RT_CH_Z][k] = (float)root->t;
  img->ch[RT_CH_ID][k] = (float)root->object;
  const rt_ray_kind_t prefer[2] = {RT_RAY_REFRACT, RT_RAY_REFLECT};
  const rt_channel_t base[2] = {RT_CH_T_U, RT_CH_R_U};
  for (int p = 0; p < 2; p++) {
    int n = rt_tree_follow(t, prefer[p]);
    double u = NAN, v = NAN;
    if (n >= 0)
      rt_plane_coords(&s->prim[t->node[n].prim].plane, t->node[n].point, &u, &v);
    img->ch[base[p]][k] = (float)u;
    img->ch[base[p] + 1][k] = (float)v;
    img->ch[base[p] + 2][k] = n >= 0 ? (float)t->node[n].depth : -1.0f;
  }
}

void rt_stats_spectral_line(const rt_stats_t *s, char *buf, size_t cap) {
  if (cap == 0)
    return;
  buf[0] = '\0';
  if (s->spectral[0] == 0)
    return;
  snprintf(buf, cap,
           "spectral pencils: %llu white refractions at dispersive glass became %llu pencils "
           "(%.2f each); dispersion not needed (never cut, within a quarter pixel) at %llu\n",
           (unsigned long long)s->spectral[0], (unsigned long long)s->spectral[1],
           (double)s->spectral[1] / (double)s->spectral[0], (unsigned long long)s->spectral[2]);
}
