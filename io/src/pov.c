/* pov.c -- a scene written as a POV-Ray 3.7 scene file (io/pov.h; issue 26's peer renderer).
 *
 * The mapping, term by term (docs/pencil.md, "POV-Ray as a peer", cites the POV-Ray 3.7
 * reference for each):
 *   camera      explicit location, direction, right and up with no look_at: POV-Ray's ray for
 *               screen point (x0, y0) in [-1/2, 1/2]^2 is direction + x0 right + y0 up, and its
 *               pixel (i, j) has x0 = (i + 1/2) / W - 1/2, y0 = 1/2 - (j + 1/2) / H; with right
 *               = 2 tan(fov/2) W/H times our unit right vector and up = -2 tan(fov/2) times our
 *               down vector that is rt_view_ray()'s ray through the same pixel centre, whatever
 *               the handedness (the vectors are given, not derived).
 *   depth       max_trace_level = max_depth + 1: POV-Ray counts the primary ray as level 1;
 *               adc_bailout 0, so that no ray is cut by its weight (ours are cut by depth only).
 *   ambient     global ambient_light = the scene's Ia, finish ambient = ka.
 *   diffuse     finish diffuse = kd (brilliance 1: kd C max(0, N.L)).
 *   Phong       finish phong = ks, phong_size = the exponent: ks (R.V)^n, white.
 *   mirror      finish reflection { kr } (constant, no Fresnel).
 *   glass       pigment transmit kt (white transmittance) or filter kt with the transmittance as
 *               the colour (kd = ka = 0), interior ior. POV-Ray scales a transparent surface's
 *               ambient and diffuse terms by its opacity 1 - kt, so they are written as
 *               ka / (1 - kt) and kd / (1 - kt).
 *   board       a checker texture of the two materials, its pattern space mapped onto the plane's
 *               (u, v) axes in units of the square, half a square off the plane along the normal
 *               (floor() of the normal coordinate is then 0 on the plane, away from rounding).
 *   lights      point lights as they are (no fade: the textbook's model), inverse-square ones
 *               with fade_power 2 and a fade_distance f 1e-4 of the radius of the scene's box
 *               (POV-Ray's 2 / (1 + (d / f)^2) is then 2 f^2 / d^2 within (f / d)^2); parallel
 *               lights from a location 1000 radii behind the box's centre along their direction.
 * "shadows": false makes every object no_shadow (a shadowless light would lose its highlights). */
#include "io/pov.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "core/camera.h"
#include "core/plan.h"
#include "io/output.h"

/* ---- names and numbers ---------------------------------------------------------------------- */

static const char *object_label(const rt_scene_t *s, int k, char *buf, size_t cap) {
  if (s->object[k].name[0])
    snprintf(buf, cap, "object %d ('%s')", k, s->object[k].name);
  else
    snprintf(buf, cap, "object %d", k);
  return buf;
}

__attribute__((format(printf, 3, 4))) static int fail(char *err, size_t cap, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, cap, fmt, ap);
  va_end(ap);
  return -1;
}

/* Appends one line to the notes buffer (may be NULL). */
__attribute__((format(printf, 3, 4))) static void note(char *notes, size_t ncap, const char *fmt,
                                                       ...) {
  if (!notes || ncap == 0)
    return;
  size_t len = strlen(notes);
  if (len + 1 >= ncap)
    return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(notes + len, ncap - len, fmt, ap);
  va_end(ap);
  len = strlen(notes);
  if (len + 1 < ncap) {
    notes[len] = '\n';
    notes[len + 1] = '\0';
  }
}

/* Every number with 17 significant digits: POV-Ray reads doubles, so the file is exact. */
static void vec(FILE *f, px_vec3_t v) {
  fprintf(f, "<%.17g, %.17g, %.17g>", v.x, v.y, v.z);
}

static void rgb(FILE *f, rt_rgb_t c) {
  fprintf(f, "<%.17g, %.17g, %.17g>", c.r, c.g, c.b);
}

static int material_used(const rt_scene_t *s, int m) {
  for (int k = 0; k < s->nobject; k++)
    if (s->object[k].material == m || s->object[k].material2 == m)
      return 1;
  return 0;
}

static int is_white(rt_rgb_t c) {
  return c.r == 1.0 && c.g == 1.0 && c.b == 1.0;
}

/* ---- what can be written ----------------------------------------------------------------------
 */

/* 1 when polygon face p is convex (its fan of triangles covers it), by the turn at each vertex
 * about its normal; the tolerance lets collinear vertices pass. */
static int face_convex(const rt_scene_t *s, const rt_polygon_t *p) {
  const px_vec3_t *v = &s->vertex[p->first];
  for (int k = 0; k < p->count; k++) {
    px_vec3_t a = px_v3_sub(v[(k + 1) % p->count], v[k]);
    px_vec3_t b = px_v3_sub(v[(k + 2) % p->count], v[(k + 1) % p->count]);
    double turn = px_v3_dot(px_v3_cross(a, b), p->n);
    if (turn < -1e-12 * px_v3_norm(a) * px_v3_norm(b))
      return 0;
  }
  return 1;
}

/* The camera and the geometry: what both kinds of file need. */
static int check_geometry(const rt_scene_t *s, const io_pov_options_t *o, char *err, size_t cap) {
  rt_view_t v;
  char lab[96];
  if (rt_view_make(&s->camera, &v) != RT_OK)
    return fail(err, cap, "the camera is not valid (rt_view_make)");
  if (o->flat && s->nobject > IO_POV_FLAT_MAX_OBJECTS)
    return fail(err, cap, "%d objects: a flat file encodes at most %d", s->nobject,
                IO_POV_FLAT_MAX_OBJECTS);
  for (int k = 0; k < s->nobject; k++) {
    const rt_object_t *ob = &s->object[k];
    if (ob->kind != RT_OBJ_POLYHEDRON)
      continue;
    for (int q = ob->first_prim; q < ob->first_prim + ob->nprim; q++)
      if (!face_convex(s, &s->prim[q].polygon))
        return fail(err, cap,
                    "%s: face %d of the polyhedron is not convex; the exporter writes faces as "
                    "fans of triangles (mesh2) and refuses faces a fan does not cover",
                    object_label(s, k, lab, sizeof lab), q - ob->first_prim);
  }
  return 0;
}

/* A material's terms: 0 when POV-Ray's finish and pigment hold them exactly. */
static int check_material(const rt_scene_t *s, int m, char *err, size_t cap) {
  const rt_material_t *mt = &s->material[m];
  if (mt->kt > 0.0 && mt->fresnel)
    return fail(err, cap,
                "material '%s': \"fresnel\": true (kt split by Fresnel's formula) is not mapped: "
                "POV-Ray 3.7's fresnel reflection does not split kt the same way",
                mt->name);
  if (mt->kt > 1.0)
    return fail(err, cap, "material '%s': kt = %g > 1 has no POV-Ray transmit", mt->name, mt->kt);
  int lit = mt->ka > 0.0 || mt->kd > 0.0;
  if (mt->kt >= 1.0 && lit)
    return fail(err, cap,
                "material '%s': kt = 1 with an ambient or diffuse term: POV-Ray scales those by "
                "the opacity 1 - kt = 0",
                mt->name);
  if (mt->kt > 0.0 && !is_white(mt->transmittance) && lit)
    return fail(err, cap,
                "material '%s': a coloured transmittance with an ambient or diffuse term: "
                "POV-Ray's filter colour is the surface colour",
                mt->name);
  return 0;
}

/* Objects whose material is transparent: closed ones only (an open surface, or a plane, which
 * POV-Ray takes for a half-space, would keep the ray in its interior), unless the index is the
 * space's. */
static int check_objects(const rt_scene_t *s, char *err, size_t cap) {
  char lab[96];
  for (int k = 0; k < s->nobject; k++) {
    const rt_object_t *ob = &s->object[k];
    for (int i = 0; i < 2; i++) {
      int m = i == 0 ? ob->material : ob->material2;
      if (m < 0 || !(s->material[m].kt > 0.0) || ob->kind == RT_OBJ_SPHERE ||
          ob->kind == RT_OBJ_POLYHEDRON || s->material[m].ior == s->ior)
        continue;
      return fail(err, cap,
                  "%s: a transparent %s of index %g: POV-Ray 3.7 would keep the refracted ray in "
                  "its interior; only spheres and polyhedra refract",
                  object_label(s, k, lab, sizeof lab),
                  ob->kind == RT_OBJ_PLANE ? "plane" : "polygon", s->material[m].ior);
    }
    if (ob->material2 >= 0 && s->material[ob->material].kt > 0.0 &&
        s->material[ob->material2].kt > 0.0 &&
        s->material[ob->material].ior != s->material[ob->material2].ior)
      return fail(err, cap, "%s: a checkerboard of two transparent materials of different indices",
                  object_label(s, k, lab, sizeof lab));
  }
  return 0;
}

/* Settings, lights, effects and materials of a shaded file. */
static int check_shading(const rt_scene_t *s, char *err, size_t cap) {
  if (s->ior != 1.0)
    return fail(err, cap,
                "settings: the space between objects has index %g; POV-Ray 3.7's is 1 (its "
                "atmosphere's index is not a scene setting)",
                s->ior);
  if (s->max_depth > 255)
    return fail(err, cap, "settings: max_depth %d: POV-Ray's max_trace_level is at most 256",
                s->max_depth);
  for (int l = 0; l < s->nlight; l++)
    if (s->light[l].kind == RT_LIGHT_AREA)
      return fail(err, cap,
                  "lights[%d]: an area light (a Lambertian rectangle drawn as an N x N mesh of "
                  "cell centres) is not POV-Ray 3.7's area_light",
                  l);
  rt_plan_t *p = malloc(sizeof *p); /* tens of kilobytes: not on the stack */
  if (!p)
    return fail(err, cap, "out of memory");
  *p = rt_plan_make(s, 1);
  int disp = rt_plan_has(p, RT_EFFECT_DISPERSION), caus = rt_plan_has(p, RT_EFFECT_CAUSTICS);
  free(p);
  const rt_material_t *dm = rt_plan_dispersive_material(s);
  if (disp)
    return fail(err, cap,
                "material '%s': a dispersive index (it varies with wavelength): not mapped to "
                "POV-Ray 3.7's dispersion, which is another model",
                dm ? dm->name : "?");
  if (caus)
    return fail(err, cap,
                "settings: the scene draws caustics (light through reflecting or transparent "
                "objects from illuminance maps): POV-Ray 3.7 would need photons; export it with "
                "\"caustics\": \"off\"");
  for (int m = 0; m < s->nmaterial; m++)
    if (material_used(s, m) && check_material(s, m, err, cap) != 0)
      return -1;
  return check_objects(s, err, cap);
}

/* The differences POV-Ray will still show, as notes. */
static void shading_notes(const rt_scene_t *s, char *notes, size_t ncap) {
  int closed_glass = 0, glass = 0, fade = 0;
  for (int k = 0; k < s->nobject; k++) {
    int t = s->material[s->object[k].material].kt > 0.0;
    glass |= t;
    closed_glass |= t && s->object[k].closed;
  }
  for (int l = 0; l < s->nlight; l++)
    fade |= s->light[l].falloff == RT_FALLOFF_INVERSE_SQUARE;
  if (closed_glass && s->shadows && s->nlight > 0)
    note(notes, ncap,
         "shadows through a transparent closed object: kt T once per object here, kt T at each "
         "of its surfaces in POV-Ray (kt^2 through a sphere)");
  if (glass && s->max_depth > 0)
    note(notes, ncap,
         "total internal reflection: the reflected ray carries kt T here, all of it in POV-Ray "
         "(a sphere of index > 1 in air never reflects totally)");
  if (fade)
    note(notes, ncap,
         "inverse-square lights: POV-Ray's fade within (f / d)^2 of 1 / d^2, f = 1e-4 of the "
         "radius of the scene's box");
  if (s->star.on)
    note(notes, ncap, "the scene's star filter (a post-process) is not part of the file");
}

/* ---- writing ----------------------------------------------------------------------------------
 */

/* The box of the finite geometry, the planes' anchor points, the eye, the point it looks at and
 * the point lights: its centre *c and the radius about it (the half-diagonal; at least 1e-6 of the
 * centre's distance from the origin, so that a scene of one point still has a size). Measured about
 * the scene, not the origin: a scene far from the origin is as well placed as one about it; and a
 * scene of planes alone still has the size of the view. */
static double scene_bounds(const rt_scene_t *s, px_vec3_t *c) {
  px_vec3_t lo = s->camera.eye, hi = s->camera.eye;
#define GROW(p, r)                                                                                 \
  do {                                                                                             \
    lo = px_vec3(fmin(lo.x, (p).x - (r)), fmin(lo.y, (p).y - (r)), fmin(lo.z, (p).z - (r)));       \
    hi = px_vec3(fmax(hi.x, (p).x + (r)), fmax(hi.y, (p).y + (r)), fmax(hi.z, (p).z + (r)));       \
  } while (0)
  GROW(s->camera.look_at, 0.0);
  for (int q = 0; q < s->nprim; q++)
    if (s->prim[q].kind == RT_PRIM_SPHERE)
      GROW(s->prim[q].sphere.c, s->prim[q].sphere.r);
    else if (s->prim[q].kind == RT_PRIM_PLANE)
      GROW(s->prim[q].plane.p, 0.0);
  for (int k = 0; k < s->nvertex; k++)
    GROW(s->vertex[k], 0.0);
  for (int l = 0; l < s->nlight; l++)
    if (s->light[l].kind == RT_LIGHT_POINT)
      GROW(s->light[l].v, 0.0);
#undef GROW
  *c = px_v3_scale(px_v3_add(lo, hi), 0.5);
  return fmax(0.5 * px_v3_norm(px_v3_sub(hi, lo)), 1e-6 * (1.0 + px_v3_norm(*c)));
}

/* Text from outside (a command line, a path, a name) in a // comment: its control characters as
 * spaces, so that a newline in a name cannot end the comment and start scene code. */
static void comment_text(FILE *f, const char *text) {
  for (const unsigned char *c = (const unsigned char *)text; *c; c++)
    fputc(*c < 0x20 || *c == 0x7f ? ' ' : *c, f);
}

static void write_header(FILE *f, const rt_scene_t *s, const io_pov_options_t *o,
                         const char *notes) {
  const io_provenance_t *pv = io_provenance();
  int side = (int)lrint(sqrt((double)o->spp));
  fprintf(f, "// POV-Ray 3.7 scene written by pencil %s (%s) on %s\n", pv->version, pv->commit,
          pv->date);
  fprintf(f, "// command: ");
  comment_text(f, pv->command_line);
  fprintf(f, "\n// scene: ");
  comment_text(f, o->source ? o->source : "(unnamed)");
  fputc('\n', f);
  fprintf(f, "// %s\n",
          o->flat ? "flat: each object's colour encodes its index (io/pov.h)"
                  : "shaded as the exact renderer shades it (io/src/pov.c)");
  fprintf(f, "// %d spp: render at %d x %d without anti-aliasing%s; each %d x %d block of\n",
          o->spp, side * s->camera.width, side * s->camera.height, side > 1 ? " and average" : "",
          side, side);
  fprintf(f, "// pixels is one pixel of the %d x %d image:\n", s->camera.width, s->camera.height);
  fprintf(f, "//   povray +IFILE.pov +W%d +H%d -A +WT1 -D%s\n", side * s->camera.width,
          side * s->camera.height, o->flat ? " +FN8 File_Gamma=1.0" : "");
  for (const char *p = notes; p && *p;) {
    const char *e = strchr(p, '\n');
    int n = e ? (int)(e - p) : (int)strlen(p);
    fprintf(f, "// note: ");
    for (int i = 0; i < n; i++) /* a name in a note: control characters as spaces */
      fputc((unsigned char)p[i] < 0x20 || p[i] == 0x7f ? ' ' : p[i], f);
    fputc('\n', f);
    p += n + (e != NULL);
  }
  fprintf(f, "#version 3.7;\n\n");
}

static void write_globals(FILE *f, const rt_scene_t *s, const io_pov_options_t *o) {
  rt_view_t v;
  rt_view_make(&s->camera, &v); /* checked before */
  fprintf(f, "global_settings {\n  assumed_gamma 1.0\n  max_trace_level %d\n  adc_bailout 0\n",
          o->flat ? 1 : s->max_depth + 1);
  fprintf(f, "  ambient_light rgb ");
  rgb(f, o->flat ? rt_rgb(0, 0, 0) : s->ambient);
  fprintf(f, "\n}\nbackground { rgb ");
  rgb(f, o->flat ? rt_rgb(0, 0, 0) : s->background);
  fprintf(f, " }\ncamera {\n  perspective\n  location ");
  vec(f, v.eye);
  fprintf(f, "\n  direction ");
  vec(f, v.forward);
  fprintf(f, "\n  right ");
  vec(f, px_v3_scale(v.right, 2.0 * v.half_w));
  fprintf(f, "\n  up ");
  vec(f, px_v3_scale(v.down, -2.0 * v.half_h));
  fprintf(f, "\n}\n\n");
}

static void write_lights(FILE *f, const rt_scene_t *s) {
  px_vec3_t centre;
  double size = scene_bounds(s, &centre), far = 1000.0 * size, fd = 1e-4 * size;
  for (int l = 0; l < s->nlight; l++) {
    const rt_light_t *L = &s->light[l];
    fprintf(f, "light_source { ");
    if (L->kind == RT_LIGHT_PARALLEL) {
      /* v is the unit direction the light travels in: from far behind the scene's box */
      px_vec3_t at = px_v3_axpy(-far, L->v, centre);
      vec(f, at);
      fprintf(f, ", rgb ");
      rgb(f, L->intensity);
      fprintf(f, " parallel point_at ");
      vec(f, px_v3_add(at, L->v));
    } else if (L->falloff == RT_FALLOFF_INVERSE_SQUARE) {
      vec(f, L->v);
      fprintf(f, ", rgb ");
      rgb(f, rt_rgb_scale(L->intensity, 0.5 / (fd * fd)));
      fprintf(f, " fade_distance %.17g fade_power 2", fd);
    } else {
      vec(f, L->v);
      fprintf(f, ", rgb ");
      rgb(f, L->intensity);
    }
    fprintf(f, " }\n");
  }
}

/* One material as a texture (and an interior when it is transparent). */
static void write_material(FILE *f, const rt_scene_t *s, int m) {
  const rt_material_t *mt = &s->material[m];
  double opacity = 1.0 - mt->kt; /* > 0 when ka or kd is: check_material() */
  fprintf(f, "// material '");
  comment_text(f, mt->name);
  fprintf(f, "'\n#declare PencilTex%d = texture {\n  pigment { ", m);
  if (!(mt->kt > 0.0)) {
    fprintf(f, "rgb ");
    rgb(f, mt->color);
  } else if (is_white(mt->transmittance)) {
    fprintf(f, "rgbt <%.17g, %.17g, %.17g, %.17g>", mt->color.r, mt->color.g, mt->color.b, mt->kt);
  } else {
    rt_rgb_t t = mt->transmittance;
    fprintf(f, "rgbf <%.17g, %.17g, %.17g, %.17g>", t.r, t.g, t.b, mt->kt);
  }
  double ka = mt->ka > 0.0 ? mt->ka / opacity : 0.0, kd = mt->kd > 0.0 ? mt->kd / opacity : 0.0;
  fprintf(f, " }\n  finish { ambient %.17g diffuse %.17g brilliance 1 specular 0", ka, kd);
  if (mt->ks > 0.0)
    fprintf(f, " phong %.17g phong_size %.17g", mt->ks, mt->phong);
  if (mt->kr > 0.0)
    fprintf(f, " reflection { %.17g }", mt->kr);
  fprintf(f, " }\n}\n");
  if (mt->kt > 0.0)
    fprintf(f, "#declare PencilInt%d = interior { ior %.17g }\n", m, mt->ior);
}

/* The flat colour of a code (io/pov.h) as a texture body. */
static void write_flat(FILE *f, unsigned code) {
  fprintf(f, "pigment { rgb <%u/255, %u/255, %u/255> } finish { ambient 0 emission 1 diffuse 0 }",
          code & 255u, (code >> 8) & 255u, code >> 16);
}

/* An object's texture, interior and flags, inside its braces. */
static void write_appearance(FILE *f, const rt_scene_t *s, const io_pov_options_t *o, int k) {
  const rt_object_t *ob = &s->object[k];
  unsigned code = (unsigned)k + 1u;
  if (ob->material2 >= 0) {
    const rt_plane_t *pl = &s->prim[ob->first_prim].plane;
    double c = pl->check;
    px_vec3_t t = px_v3_axpy(-0.5 * c, pl->n, pl->p);
    fprintf(f, "  texture { checker\n    texture { ");
    if (o->flat)
      write_flat(f, code);
    else
      fprintf(f, "PencilTex%d", ob->material);
    fprintf(f, " }\n    texture { ");
    if (o->flat)
      write_flat(f, code | IO_POV_ODD);
    else
      fprintf(f, "PencilTex%d", ob->material2);
    fprintf(f,
            " }\n    matrix <%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g, "
            "%.17g, %.17g, %.17g>\n  }\n",
            c * pl->u.x, c * pl->u.y, c * pl->u.z, c * pl->v.x, c * pl->v.y, c * pl->v.z,
            c * pl->n.x, c * pl->n.y, c * pl->n.z, t.x, t.y, t.z);
  } else if (o->flat) {
    fprintf(f, "  texture { ");
    write_flat(f, code);
    fprintf(f, " }\n");
  } else {
    fprintf(f, "  texture { PencilTex%d }\n", ob->material);
  }
  if (!o->flat) {
    int m =
        ob->material2 >= 0 && s->material[ob->material2].kt > 0.0 ? ob->material2 : ob->material;
    if (s->material[m].kt > 0.0)
      fprintf(f, "  interior { PencilInt%d }\n", m);
    if (!s->shadows)
      fprintf(f, "  no_shadow\n");
  }
}

static void write_polyhedron(FILE *f, const rt_scene_t *s, const rt_object_t *ob) {
  int nv = 0, nt = 0;
  for (int q = ob->first_prim; q < ob->first_prim + ob->nprim; q++) {
    nv += s->prim[q].polygon.count;
    nt += s->prim[q].polygon.count - 2;
  }
  fprintf(f, "mesh2 {\n  vertex_vectors { %d", nv);
  for (int q = ob->first_prim; q < ob->first_prim + ob->nprim; q++)
    for (int i = 0; i < s->prim[q].polygon.count; i++) {
      fprintf(f, ",\n    ");
      vec(f, s->vertex[s->prim[q].polygon.first + i]);
    }
  fprintf(f, " }\n  face_indices { %d", nt);
  int base = 0;
  for (int q = ob->first_prim; q < ob->first_prim + ob->nprim; q++) {
    int n = s->prim[q].polygon.count;
    for (int i = 1; i + 1 < n; i++) /* a fan: the face is convex (check_geometry) */
      fprintf(f, ",\n    <%d, %d, %d>", base, base + i, base + i + 1);
    base += n;
  }
  fprintf(f, " }\n  inside_vector <0, 0, 1>\n");
}

static void write_object(FILE *f, const rt_scene_t *s, const io_pov_options_t *o, int k) {
  const rt_object_t *ob = &s->object[k];
  const rt_prim_t *p = &s->prim[ob->first_prim];
  char lab[96];
  fprintf(f, "// ");
  comment_text(f, object_label(s, k, lab, sizeof lab));
  fputc('\n', f);
  switch (ob->kind) {
  case RT_OBJ_SPHERE:
    fprintf(f, "sphere { ");
    vec(f, p->sphere.c);
    fprintf(f, ", %.17g\n", p->sphere.r);
    break;
  case RT_OBJ_PLANE:
    fprintf(f, "plane { ");
    vec(f, p->plane.n);
    fprintf(f, ", %.17g\n", px_v3_dot(p->plane.n, p->plane.p));
    break;
  case RT_OBJ_POLYGON:
    fprintf(f, "polygon { %d", p->polygon.count + 1); /* closed: the first vertex again */
    for (int i = 0; i <= p->polygon.count; i++) {
      fprintf(f, ", ");
      vec(f, s->vertex[p->polygon.first + i % p->polygon.count]);
    }
    fprintf(f, "\n");
    break;
  case RT_OBJ_POLYHEDRON:
    write_polyhedron(f, s, ob);
    break;
  }
  write_appearance(f, s, o, k);
  fprintf(f, "}\n");
}

int io_pov_check(const rt_scene_t *s, const io_pov_options_t *o, char *notes, size_t ncap,
                 char *err, size_t cap) {
  if (notes && ncap > 0)
    notes[0] = '\0';
  int side = (int)lrint(sqrt((double)o->spp));
  if (o->spp < 1 || side * side != o->spp)
    return fail(err, cap, "samples per pixel %d: expected a square, 1, 4, 9, ...", o->spp);
  if (check_geometry(s, o, err, cap) != 0 || (!o->flat && check_shading(s, err, cap) != 0))
    return -1;
  if (!o->flat)
    shading_notes(s, notes, ncap);
  return 0;
}

int io_pov_write(FILE *f, const rt_scene_t *s, const io_pov_options_t *o, char *notes, size_t ncap,
                 char *err, size_t cap) {
  char local[1024];
  if (!notes || ncap == 0)
    notes = local, ncap = sizeof local;
  if (io_pov_check(s, o, notes, ncap, err, cap) != 0)
    return -1;
  write_header(f, s, o, notes);
  write_globals(f, s, o);
  if (!o->flat) {
    write_lights(f, s);
    for (int m = 0; m < s->nmaterial; m++)
      if (material_used(s, m))
        write_material(f, s, m);
  }
  fprintf(f, "\n");
  for (int k = 0; k < s->nobject; k++)
    write_object(f, s, o, k);
  return ferror(f) ? fail(err, cap, "write error") : 0;
}

int io_pov_export(const char *path, const rt_scene_t *s, const io_pov_options_t *o, char *notes,
                  size_t ncap, char *err, size_t cap) {
  io_atomic_t a;
  if (io_pov_check(s, o, notes, ncap, err, cap) != 0 || io_atomic_open(&a, path, err, cap) != 0)
    return -1;
  if (io_pov_write(a.f, s, o, notes, ncap, err, cap) != 0) {
    io_atomic_abort(&a);
    return fail(err, cap, "%s: write error", path);
  }
  return io_atomic_commit(&a, err, cap);
}
