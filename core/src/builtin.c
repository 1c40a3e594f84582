/* builtin.c -- scenes constructed in C: the paper's Fig. 8 (section 5: "a transparent sphere
 * over a checkerboard", 256 x 256, nine rays per pixel) and a 1,000-polygon faceted sphere for
 * the benchmark. The paper gives no radius, index, camera or light; scenes/README.md records
 * the values chosen here, and scenes/fig8.json is the same scene as a file. */
#include "core/builtin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static rt_material_t glass(void) {
  rt_material_t m = rt_material_default("glass");
  m.ka = 0.0;
  m.kd = 0.0;
  m.ks = 0.6;
  m.phong = 80.0;
  m.kr = 0.15;
  m.kt = 0.75;
  m.ior = 1.5;
  return m;
}

static rt_material_t matte(const char *name, double r, double g, double b) {
  rt_material_t m = rt_material_default(name);
  m.color = rt_rgb(r, g, b);
  m.ka = 0.2;
  m.kd = 0.8;
  return m;
}

/* Camera, light, ambient, background and the checkerboard y = 0 shared by the built-ins. */
static rt_status_t stage(rt_scene_t *s) {
  s->camera = (rt_camera_t){{0.0, 3.0, -6.0}, {0.0, 0.9, 0.0}, {0, 1, 0}, 40.0, 256, 256};
  s->ambient = rt_rgb(1, 1, 1);
  s->background = rt_rgb(0.35, 0.55, 0.85);
  s->max_depth = 6;
  s->caustics = RT_CAUSTICS_OFF; /* the paper's Whitted image, with the textbook's shadow */
  s->spp = 9;
  rt_material_t white = matte("white", 0.9, 0.9, 0.9), red = matte("red", 0.85, 0.12, 0.1);
  int mw, mr;
  rt_light_t light = {
      RT_LIGHT_POINT, {-5.0, 6.0, -2.5}, {1.0, 1.0, 1.0}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0};
  rt_status_t st = rt_scene_add_material(s, &white, &mw);
  if (st == RT_OK)
    st = rt_scene_add_material(s, &red, &mr);
  if (st == RT_OK)
    st = rt_scene_add_plane(s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mw, mr, 1.0,
                            NULL);
  if (st == RT_OK)
    st = rt_scene_add_light(s, &light);
  return st;
}

rt_status_t rt_builtin_fig8(rt_scene_t *s) {
  rt_material_t g = glass();
  int mg, ball;
  rt_status_t st = stage(s);
  if (st == RT_OK)
    st = rt_scene_add_material(s, &g, &mg);
  if (st == RT_OK)
    st = rt_scene_add_sphere(s, px_vec3(0.0, 1.5, 0.0), 1.0, mg, &ball);
  if (st == RT_OK) {
    rt_scene_name_object(s, 0, "checkerboard");
    rt_scene_name_object(s, ball, "glass ball");
    st = rt_scene_prepare(s);
  }
  return st;
}

/* Vertex index of ring k (1..stacks-1), slice i; 0 and nv-1 are the poles. */
static int ring_vertex(int k, int i, int slices) {
  return 1 + (k - 1) * slices + i % slices;
}

static void fill_faces(int stacks, int slices, int nv, int *idx, int *len) {
  int f = 0, o = 0;
  for (int k = 0; k < stacks; k++)
    for (int i = 0; i < slices; i++) {
      if (k == 0) { /* cap around the north pole */
        int t[3] = {0, ring_vertex(1, i + 1, slices), ring_vertex(1, i, slices)};
        memcpy(idx + o, t, sizeof t);
        len[f++] = 3;
        o += 3;
      } else if (k == stacks - 1) { /* cap around the south pole */
        int t[3] = {nv - 1, ring_vertex(k, i, slices), ring_vertex(k, i + 1, slices)};
        memcpy(idx + o, t, sizeof t);
        len[f++] = 3;
        o += 3;
      } else { /* a planar isosceles trapezoid between two rings */
        int q[4] = {ring_vertex(k, i, slices), ring_vertex(k, i + 1, slices),
                    ring_vertex(k + 1, i + 1, slices), ring_vertex(k + 1, i, slices)};
        memcpy(idx + o, q, sizeof q);
        len[f++] = 4;
        o += 4;
      }
    }
}

rt_status_t rt_scene_add_faceted_sphere(rt_scene_t *s, px_vec3_t c, double r, int stacks,
                                        int slices, int material, int *object) {
  if (stacks < 2 || slices < 3 || stacks > 4096 || slices > 4096 || !(r > 0.0))
    return RT_EINVAL;
  int nv = 2 + (stacks - 1) * slices, nf = stacks * slices;
  px_vec3_t *v = malloc((size_t)nv * sizeof *v);
  int *idx = malloc((size_t)nf * 4 * sizeof *idx), *len = malloc((size_t)nf * sizeof *len);
  rt_status_t st = RT_ENOMEM;
  if (v && idx && len) {
    v[0] = px_vec3(c.x, c.y + r, c.z);
    v[nv - 1] = px_vec3(c.x, c.y - r, c.z);
    for (int k = 1; k < stacks; k++)
      for (int i = 0; i < slices; i++) {
        double th = M_PI * k / stacks, ph = 2.0 * M_PI * i / slices;
        v[ring_vertex(k, i, slices)] =
            px_vec3(c.x + r * sin(th) * cos(ph), c.y + r * cos(th), c.z + r * sin(th) * sin(ph));
      }
    fill_faces(stacks, slices, nv, idx, len);
    st = rt_scene_add_polyhedron(s, v, nv, idx, len, nf, material, object, NULL, 0);
  }
  free(v);
  free(idx);
  free(len);
  return st;
}

rt_status_t rt_builtin_mesh(rt_scene_t *s, int stacks, int slices) {
  rt_material_t g = glass();
  int mg, ball;
  rt_status_t st = stage(s);
  if (st == RT_OK)
    st = rt_scene_add_material(s, &g, &mg);
  if (st == RT_OK)
    st = rt_scene_add_faceted_sphere(s, px_vec3(0.0, 1.5, 0.0), 1.0, stacks, slices, mg, &ball);
  if (st == RT_OK) {
    rt_scene_name_object(s, 0, "checkerboard");
    rt_scene_name_object(s, ball, "faceted glass ball");
    st = rt_scene_prepare(s);
  }
  return st;
}

rt_status_t rt_builtin(const char *name, rt_scene_t *s) {
  if (strcmp(name, "fig8") == 0)
    return rt_builtin_fig8(s);
  if (strcmp(name, "mesh1000") == 0)
    return rt_builtin_mesh(s, 25, 40);
  return RT_EINVAL;
}
