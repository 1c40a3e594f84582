/* scene_json.c -- loading a scene file (docs/scene-format.md) with jansson: camera, settings,
 * materials and lights here; objects in scene_objects.c. The model is the textbook's (9.1):
 * ambient, diffuse, Phong specular, coherent reflection kr and refraction kt, point and
 * parallel lights, a pinhole camera. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/camera.h"
#include "core/intersect.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "parse.h"
#include "post/star.h"

static int parse_camera(io_parse_t *P, json_t *c) {
  static const char *const keys[] = {"eye", "look_at", "up", "fov", "width", "height", NULL};
  rt_camera_t *cam = &P->scene->camera;
  io_push_key(P, "camera");
  int ok = io_check_keys(P, c, keys) && io_get_vec3(P, c, "eye", 1, cam->eye, &cam->eye) &&
           io_get_vec3(P, c, "look_at", 1, cam->look_at, &cam->look_at) &&
           io_get_vec3(P, c, "up", 0, px_vec3(0, 1, 0), &cam->up) &&
           io_get_number(P, c, "fov", 0, 40.0, 0.0, 179.0, 1, &cam->fov_deg) &&
           io_get_int(P, c, "width", 0, 256, 1, 16384, &cam->width) &&
           io_get_int(P, c, "height", 0, 256, 1, 16384, &cam->height);
  rt_view_t view;
  if (ok && rt_view_make(cam, &view) != RT_OK)
    ok = io_fail(P, "eye and look_at must differ and up must not be parallel to the view");
  io_pop(P);
  return ok;
}

static int parse_settings(io_parse_t *P, json_t *o) {
  static const char *const keys[] = {"ambient", "background", "max_depth",     "spp", "shadows",
                                     "ior",     "caustics",   "spectral_bins", NULL};
  rt_scene_t *s = P->scene;
  io_push_key(P, "settings");
  int ok = io_check_keys(P, o, keys) && io_get_rgb(P, o, "ambient", s->ambient, &s->ambient) &&
           io_get_rgb(P, o, "background", s->background, &s->background) &&
           io_get_int(P, o, "max_depth", 0, s->max_depth, 0, 32, &s->max_depth) &&
           io_get_int(P, o, "spp", 0, s->spp, 1, RT_MAX_SPP, &s->spp) &&
           io_get_bool(P, o, "shadows", 1, &s->shadows) &&
           io_get_number(P, o, "ior", 0, 1.0, RT_IOR_MIN, RT_IOR_MAX, 0, &s->ior) &&
           io_get_int(P, o, "spectral_bins", 0, s->spectral_bins, RT_MIN_BINS, RT_MAX_BINS,
                      &s->spectral_bins);
  const char *caustics = NULL;
  ok = ok && io_get_string(P, o, "caustics", 0, &caustics);
  if (ok && caustics && strcmp(caustics, "off") == 0) {
    s->caustics = RT_CAUSTICS_OFF;
  } else if (ok && caustics && strcmp(caustics, "auto") != 0) {
    io_push_key(P, "caustics");
    if (strcmp(caustics, "on") == 0)
      ok = io_fail(P, "\"on\" is not available yet: no renderer draws caustics (issue 25); "
                      "expected \"auto\" or \"off\"");
    else
      ok = io_fail(P, "expected \"auto\" or \"off\", got '%s'", caustics);
    io_pop(P);
  }
  int root = (int)lrint(sqrt(s->spp));
  if (ok && root * root != s->spp) {
    io_push_key(P, "spp");
    ok = io_fail(P, "expected a square number of samples per pixel (1, 4, 9, ..., %d), got %d",
                 RT_MAX_SPP, s->spp);
    io_pop(P);
  }
  io_pop(P);
  return ok;
}

/* A material's "ior": a number (the index at every wavelength), or a model (docs/scene-format.md):
 * {"glass": NAME}, {"model": "abbe", "nd": .., "vd": ..}, {"model": "cauchy", "A": .., "B_um2": ..,
 * "C_um4": ..} or {"model": "sellmeier", "B": [..], "C_um2": [..], "range_nm": [lo, hi]}. A model
 * must hold on 380..780 nm with a finite index >= 1 there; ior is its value at the d-line. */
static int parse_ior(io_parse_t *P, json_t *o, rt_material_t *m) {
  json_t *v = json_object_get(o, "ior");
  if (!v || json_is_number(v)) {
    int ok = io_get_number(P, o, "ior", 0, m->ior, RT_IOR_MIN, RT_IOR_MAX, 0, &m->ior);
    m->index = px_index_constant(m->ior);
    return ok;
  }
  io_push_key(P, "ior");
  int ok = 1;
  px_index_t x;
  memset(&x, 0, sizeof x);
  const char *glass = NULL, *model = NULL;
  if (!json_is_object(v)) {
    ok = io_fail(P, "expected a number or an index model {\"glass\": ...} or {\"model\": ...}");
  } else if (json_object_get(v, "glass")) {
    static const char *const keys[] = {"glass", NULL};
    ok = io_check_keys(P, v, keys) && io_get_string(P, v, "glass", 1, &glass);
    if (ok && px_index_named(glass, &x) != PX_OK) {
      io_push_key(P, "glass");
      ok = io_fail(P, "no glass '%s' in the catalogue (%s)", glass, px_index_names());
      io_pop(P);
    }
  } else if (!(ok = io_get_string(P, v, "model", 1, &model))) {
  } else if (strcmp(model, "abbe") == 0) {
    static const char *const keys[] = {"model", "nd", "vd", NULL};
    double nd, vd;
    ok = io_check_keys(P, v, keys) && io_get_number(P, v, "nd", 1, 0, 1.0, 10.0, 1, &nd) &&
         io_get_number(P, v, "vd", 1, 0, 0.0, 1000.0, 1, &vd) &&
         px_index_from_abbe(nd, vd, &x) == PX_OK;
  } else if (strcmp(model, "cauchy") == 0) {
    static const char *const keys[] = {"model", "A", "B_um2", "C_um4", NULL};
    x.kind = PX_INDEX_CAUCHY;
    x.lo_nm = 380.0;
    x.hi_nm = 780.0;
    ok = io_check_keys(P, v, keys) && io_get_number(P, v, "A", 1, 0, 0.0, 10.0, 1, &x.a) &&
         io_get_number(P, v, "B_um2", 0, 0, -10.0, 10.0, 0, &x.b[0]) &&
         io_get_number(P, v, "C_um4", 0, 0, -10.0, 10.0, 0, &x.b[1]);
  } else if (strcmp(model, "sellmeier") == 0) {
    static const char *const keys[] = {"model", "B", "C_um2", "range_nm", NULL};
    json_t *b = json_object_get(v, "B"), *c = json_object_get(v, "C_um2"),
           *r = json_object_get(v, "range_nm");
    x.kind = PX_INDEX_SELLMEIER;
    x.lo_nm = 380.0;
    x.hi_nm = 780.0;
    ok = io_check_keys(P, v, keys);
    if (ok && (!json_is_array(b) || !json_is_array(c) || json_array_size(b) < 1 ||
               json_array_size(b) > PX_SELLMEIER_TERMS || json_array_size(b) != json_array_size(c)))
      ok = io_fail(P, "expected \"B\" and \"C_um2\", arrays of 1 to 4 numbers of equal length");
    for (size_t k = 0; ok && k < json_array_size(b); k++) {
      if (!json_is_number(json_array_get(b, k)) || !json_is_number(json_array_get(c, k)))
        ok = io_fail(P, "\"B\" and \"C_um2\" must hold numbers");
      else {
        x.b[k] = json_number_value(json_array_get(b, k));
        x.c[k] = json_number_value(json_array_get(c, k));
      }
    }
    x.nterm = (int)json_array_size(b);
    if (ok && r) {
      io_push_key(P, "range_nm");
      if (!json_is_array(r) || json_array_size(r) != 2 || !json_is_number(json_array_get(r, 0)) ||
          !json_is_number(json_array_get(r, 1)))
        ok = io_fail(P, "expected [lo, hi] in nm");
      else {
        x.lo_nm = json_number_value(json_array_get(r, 0));
        x.hi_nm = json_number_value(json_array_get(r, 1));
      }
      io_pop(P);
    }
  } else {
    io_push_key(P, "model");
    ok = io_fail(P,
                 "expected \"abbe\", \"cauchy\" or \"sellmeier\" (or {\"glass\": NAME}), got '%s'",
                 model);
    io_pop(P);
  }
  /* the model must hold over the visible range with a finite index >= 1: no Sellmeier pole
   * inside it (where n^2 runs to -infinity on one side, between any two grid points), and the
   * index checked at every nm */
  for (int k = 0; ok && x.kind == PX_INDEX_SELLMEIER && k < x.nterm; k++) {
    double pole = 1000.0 * sqrt(x.c[k]);
    if (x.c[k] > 0.0 && pole >= 380.0 && pole <= 780.0) {
      io_push_key(P, "C_um2");
      ok = io_fail(P, "term %d has its pole at %.4g nm (C_um2 = %g), inside 380 to 780 nm", k + 1,
                   pole, x.c[k]);
      io_pop(P);
    }
  }
  for (double l = 380.0; ok && l <= 780.0; l += 1.0) {
    double n;
    if (px_index_eval(&x, l, &n, NULL) != PX_OK || !(n >= 1.0) || n > RT_IOR_MAX)
      ok = io_fail(
          P, "the model does not give an index >= 1 at %g nm (it must hold on 380 to 780 nm)", l);
  }
  if (ok) {
    px_index_eval(&x, PX_LAMBDA_D, &m->ior, NULL);
    m->index = x;
  }
  io_pop(P);
  return ok;
}

static int parse_material(io_parse_t *P, const char *name, json_t *o) {
  static const char *const keys[] = {
      "color", "ka", "kd", "ks", "phong", "kr", "kt", "ior", "fresnel", "transmittance", NULL};
  rt_material_t m = rt_material_default(name);
  if (strlen(name) >= RT_NAME_MAX || !name[0])
    return io_fail(P, "material names must have 1 to %d characters", RT_NAME_MAX - 1);
  if (!json_is_object(o))
    return io_fail(P, "expected a material object {\"kd\": ..., ...}");
  int ok = io_check_keys(P, o, keys) && io_get_rgb(P, o, "color", m.color, &m.color) &&
           io_get_number(P, o, "ka", 0, m.ka, 0, 1, 0, &m.ka) &&
           io_get_number(P, o, "kd", 0, m.kd, 0, 1, 0, &m.kd) &&
           io_get_number(P, o, "ks", 0, m.ks, 0, 1, 0, &m.ks) &&
           io_get_number(P, o, "phong", 0, m.phong, 0, 1e6, 0, &m.phong) &&
           io_get_number(P, o, "kr", 0, m.kr, 0, 1, 0, &m.kr) &&
           io_get_number(P, o, "kt", 0, m.kt, 0, 1, 0, &m.kt) && parse_ior(P, o, &m) &&
           io_get_bool(P, o, "fresnel", 0, &m.fresnel) &&
           io_get_rgb(P, o, "transmittance", m.transmittance, &m.transmittance);
  rt_status_t st = ok ? rt_scene_add_material(P->scene, &m, NULL) : RT_OK;
  if (st != RT_OK)
    return st == RT_ENOMEM ? io_enomem(P) : io_fail(P, "invalid material");
  return ok;
}

static int parse_materials(io_parse_t *P, json_t *o) {
  const char *name;
  json_t *v;
  io_push_key(P, "materials");
  int ok = 1;
  json_object_foreach(o, name, v) {
    io_push_key(P, name);
    ok = parse_material(P, name, v);
    io_pop(P);
    if (!ok)
      break;
  }
  io_pop(P);
  return ok;
}

static int parse_light(io_parse_t *P, json_t *o) {
  static const char *const keys[] = {"type",   "position", "direction", "intensity", "falloff",
                                     "center", "edge_u",   "edge_v",    "samples",   NULL};
  const char *type;
  rt_light_t l = {RT_LIGHT_POINT, {0, 0, 0}, {1, 1, 1}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0};
  if (!json_is_object(o))
    return io_fail(P, "expected a light object {\"type\": \"point\", ...}");
  if (!io_check_keys(P, o, keys) || !io_get_string(P, o, "type", 1, &type) ||
      !io_get_rgb(P, o, "intensity", l.intensity, &l.intensity))
    return 0;
  if (strcmp(type, "area") != 0 && (json_object_get(o, "center") || json_object_get(o, "edge_u") ||
                                    json_object_get(o, "edge_v") || json_object_get(o, "samples")))
    return io_fail(P, "\"center\", \"edge_u\", \"edge_v\" and \"samples\" belong to an area "
                      "light");
  if (strcmp(type, "area") == 0) {
    l.kind = RT_LIGHT_AREA;
    if (json_object_get(o, "position") || json_object_get(o, "direction"))
      return io_fail(P, "an area light has a \"center\" and edges \"edge_u\", \"edge_v\", not a "
                        "\"position\" or \"direction\"");
    if (json_object_get(o, "falloff"))
      return io_fail(P, "an area light has no \"falloff\" (it always falls off as the inverse "
                        "square)");
    if (!io_get_vec3(P, o, "center", 1, l.v, &l.v) ||
        !io_get_vec3(P, o, "edge_u", 1, l.eu, &l.eu) ||
        !io_get_vec3(P, o, "edge_v", 1, l.ev, &l.ev) ||
        !io_get_int(P, o, "samples", 0, RT_AREA_SAMPLES_DEFAULT, 1, RT_MAX_AREA_SAMPLES,
                    &l.samples))
      return 0;
    px_vec3_t n = px_v3_cross(l.eu, l.ev);
    if (!(px_v3_norm(n) > 1e-12 * px_v3_norm(l.eu) * px_v3_norm(l.ev))) {
      io_push_key(P, "edge_v");
      io_fail(P, "the edges span no area (zero or parallel)");
      io_pop(P);
      return 0;
    }
  } else if (strcmp(type, "point") == 0) {
    if (json_object_get(o, "direction"))
      return io_fail(P, "a point light has a \"position\", not a \"direction\"");
    if (!io_get_vec3(P, o, "position", 1, l.v, &l.v))
      return 0;
    const char *falloff; /* NULL when absent: the textbook's no fall-off */
    if (!io_get_string(P, o, "falloff", 0, &falloff))
      return 0;
    if (falloff && strcmp(falloff, "inverse-square") == 0) {
      l.falloff = RT_FALLOFF_INVERSE_SQUARE;
    } else if (falloff && strcmp(falloff, "none") != 0) {
      io_push_key(P, "falloff");
      io_fail(P, "unknown fall-off '%s'; expected \"none\" or \"inverse-square\"", falloff);
      io_pop(P);
      return 0;
    }
  } else if (strcmp(type, "parallel") == 0) {
    if (json_object_get(o, "falloff"))
      return io_fail(P, "a parallel light has no \"falloff\" (it is equally bright everywhere)");
    l.kind = RT_LIGHT_PARALLEL;
    if (json_object_get(o, "position"))
      return io_fail(P, "a parallel light has a \"direction\", not a \"position\"");
    if (!io_get_vec3(P, o, "direction", 1, l.v, &l.v))
      return 0;
    if (px_vec3_norm(l.v) == 0.0) {
      io_push_key(P, "direction");
      io_fail(P, "expected a non-zero direction vector");
      io_pop(P);
      return 0;
    }
  } else {
    io_push_key(P, "type");
    io_fail(P, "unknown light type '%s'; expected \"point\", \"parallel\" or \"area\"", type);
    io_pop(P);
    return 0;
  }
  rt_status_t st = rt_scene_add_light(P->scene, &l);
  return st == RT_OK ? 1 : st == RT_ENOMEM ? io_enomem(P) : io_fail(P, "invalid light");
}

static int parse_lights(io_parse_t *P, json_t *arr) {
  io_push_key(P, "lights");
  int ok = 1;
  for (size_t i = 0; i < json_array_size(arr) && ok; i++) {
    io_push_index(P, (int)i);
    ok = parse_light(P, json_array_get(arr, i));
    io_pop(P);
  }
  io_pop(P);
  return ok;
}

/* "post": {"star": {...}}: the cross-screen filter after rendering (docs/star.md); absent keys
 * take post/star.h's defaults. */
static int parse_post(io_parse_t *P, json_t *o) {
  static const char *const keys[] = {"star", NULL};
  static const char *const star_keys[] = {"directions", "angle", "ratio", "sigma",
                                          "weight2",    "ior",   "focal", "frame",
                                          "exposure",   "white", NULL};
  json_t *st;
  io_push_key(P, "post");
  int ok = io_check_keys(P, o, keys) && io_get_object(P, o, "star", 0, &st);
  if (ok && st) {
    pp_star_t d = PP_STAR_DEFAULT;
    rt_star_t *r = &P->scene->star;
    io_push_key(P, "star");
    r->on = 1;
    r->sigma1 = d.sigma1;
    r->sigma2 = d.sigma2;
    ok = io_check_keys(P, st, star_keys) &&
         io_get_int(P, st, "directions", 0, d.directions, 1, 16, &r->directions) &&
         io_get_number(P, st, "angle", 0, d.angle_deg, -360.0, 360.0, 0, &r->angle_deg) &&
         io_get_number(P, st, "ratio", 0, d.ratio, 0.0, 0.999999, 0, &r->ratio) &&
         io_get_number(P, st, "weight2", 0, d.weight2, 0.0, 1.0, 0, &r->weight2) &&
         io_get_number(P, st, "ior", 0, d.ior, 1.0, 10.0, 1, &r->ior) &&
         io_get_number(P, st, "focal", 0, d.focal_mm, 0.0, 1e5, 1, &r->focal_mm) &&
         io_get_number(P, st, "frame", 0, d.frame_mm, 0.0, 1e5, 1, &r->frame_mm) &&
         io_get_number(P, st, "exposure", 0, 1.0, 0.0, 1e12, 1, &r->exposure) &&
         io_get_number(P, st, "white", 0, 4.0, 0.0, 1e12, 1, &r->white);
    json_t *sg;
    if (ok && (sg = json_object_get(st, "sigma")) != NULL) {
      io_push_key(P, "sigma");
      double a = json_number_value(json_array_get(sg, 0)),
             b = json_number_value(json_array_get(sg, 1));
      if (!json_is_array(sg) || json_array_size(sg) != 2 ||
          !json_is_number(json_array_get(sg, 0)) || !json_is_number(json_array_get(sg, 1)) ||
          !(a > 0.0 && a <= 10.0) || !(b > 0.0 && b <= 10.0))
        ok = io_fail(P, "expected [sigma1, sigma2], two slopes in (0, 10]");
      else {
        r->sigma1 = a;
        r->sigma2 = b;
      }
      io_pop(P);
    }
    io_pop(P);
  }
  io_pop(P);
  return ok;
}

static int parse_root(io_parse_t *P, json_t *root) {
  static const char *const keys[] = {"camera",  "settings", "materials", "lights",
                                     "objects", "post",     NULL};
  json_t *cam, *set, *mat, *lights, *objs, *post;
  if (!json_is_object(root))
    return io_fail(P, "expected the scene to be one JSON object {\"camera\": ..., ...}");
  if (!io_check_keys(P, root, keys) || !io_get_object(P, root, "camera", 1, &cam) ||
      !io_get_object(P, root, "settings", 0, &set) ||
      !io_get_object(P, root, "materials", 0, &mat) ||
      !io_get_array(P, root, "lights", 0, &lights) || !io_get_array(P, root, "objects", 1, &objs) ||
      !io_get_object(P, root, "post", 0, &post))
    return 0;
  return parse_camera(P, cam) && (!set || parse_settings(P, set)) &&
         (!mat || parse_materials(P, mat)) && (!lights || parse_lights(P, lights)) &&
         io_parse_objects(P, objs) && (!post || parse_post(P, post));
}

/* A JSON syntax error as "NAME:LINE:COLUMN: invalid JSON: ..." (or "NAME: ..." without a line,
 * e.g. a file that cannot be opened); returns -1, or -2 when jansson ran out of memory. */
static int json_syntax_error(const char *name, const json_error_t *je, char *err, size_t cap) {
  if (json_error_code(je) == json_error_out_of_memory)
    return snprintf(err, cap, "%s: out of memory", name), -2;
  if (je->line > 0)
    snprintf(err, cap, "%s:%d:%d: invalid JSON: %s", name, je->line, je->column, je->text);
  else
    snprintf(err, cap, "%s: %s", name, je->text);
  return -1;
}

/* The eye must not be inside a closed object that transmits light: every renderer starts its
 * primary rays in the scene's medium (settings.ior), and rays leaving such an object from inside
 * would pass its surface unrefracted. An opaque one (a room) is fine: its inside is what is seen.
 */
static int eye_outside(io_parse_t *P) {
  const rt_scene_t *s = P->scene;
  int o = rt_medium_object(s, s->camera.eye);
  if (o < 0)
    return 1;
  const rt_object_t *ob = &s->object[o];
  int clear = s->material[ob->material].kt > 0.0 ||
              (ob->material2 >= 0 && s->material[ob->material2].kt > 0.0);
  if (!clear)
    return 1;
  char label[32];
  if (!ob->name[0])
    snprintf(label, sizeof label, "object %d", o);
  io_push_key(P, "camera");
  io_push_key(P, "eye");
  io_fail(P,
          "the eye is inside '%s', which transmits light; the eye must be in the scene's medium "
          "(rays leaving the object from inside would not refract)",
          ob->name[0] ? ob->name : label);
  io_pop(P);
  io_pop(P);
  return 0;
}

/* Parse the document `root` (released here) into s and prepare it; text[len] is the source when
 * it is in memory (NULL: errors read `name` again to find their line). */
static int load_root(const char *name, const char *text, size_t len, json_t *root, rt_scene_t *s,
                     char *err, size_t cap) {
  io_parse_t P = {.file = name, .text = text, .len = len, .err = err, .cap = cap, .scene = s};
  int ok = parse_root(&P, root);
  json_decref(root);
  rt_status_t st = ok ? rt_scene_prepare(s) : RT_OK;
  if (ok && st != RT_OK) {
    snprintf(err, cap, "%s: the scene cannot be prepared: %s", name, rt_strerror(st));
    ok = 0;
  }
  if (ok)
    ok = eye_outside(&P);
  if (!ok)
    rt_scene_free(s);
  return ok ? 0 : P.oom || st == RT_ENOMEM ? -2 : -1;
}

/* The length of a UTF-8 byte order mark at data[0 .. len-1] (3), or 0. Editors on Windows write
 * one; JSON (RFC 8259, 8.1) lets a parser ignore it, and jansson does not: it is skipped. */
static size_t bom(const char *data, size_t len) {
  return len >= 3 && memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

int io_scene_load(const char *path, rt_scene_t *s, char *err, size_t cap) {
  json_error_t je;
  rt_scene_free(s);
  struct stat st; /* a pipe would be waited on for ever, a directory read as an empty file */
  if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
    snprintf(err, cap, "%s: not a regular file (%s)", path,
             S_ISDIR(st.st_mode) ? "a directory" : "a device, pipe or socket");
    return -1;
  }
  char head[3];
  FILE *f = fopen(path, "rb");
  size_t got = f ? fread(head, 1, sizeof head, f) : 0;
  if (f)
    fclose(f);
  if (bom(head, got)) { /* read whole, from memory past the mark: lines stay the file's */
    size_t len;
    char *text = io_read_file(path, &len);
    if (!text)
      return snprintf(err, cap, "%s: cannot read the file", path), -1;
    json_t *root = json_loadb(text + 3, len - 3, JSON_REJECT_DUPLICATES, &je);
    if (root)
      io_protect_input(path);
    int rc = root ? load_root(path, text + 3, len - 3, root, s, err, cap)
                  : json_syntax_error(path, &je, err, cap);
    free(text);
    return rc;
  }
  json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
  if (root)
    io_protect_input(path); /* no output of this run replaces it */
  return root ? load_root(path, NULL, 0, root, s, err, cap)
              : json_syntax_error(path, &je, err, cap);
}

int io_scene_load_buffer(const char *name, const char *data, size_t len, rt_scene_t *s, char *err,
                         size_t cap) {
  json_error_t je;
  rt_scene_free(s);
  size_t skip = bom(data, len);
  data += skip;
  len -= skip;
  json_t *root = json_loadb(data, len, JSON_REJECT_DUPLICATES, &je);
  return root ? load_root(name, data, len, root, s, err, cap)
              : json_syntax_error(name, &je, err, cap);
}
