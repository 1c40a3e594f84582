/* scene.h -- the scene model of the reference renderer: materials, objects (spheres, checkered
 * planes, polygons, closed polyhedra), point and parallel lights, a pinhole camera (textbook
 * sections 9.1-9.2; course notes 1.7).
 *
 * A scene is built with the rt_scene_add_*() functions, then rt_scene_prepare() builds the BVH;
 * after that it is read-only and may be traced from any number of threads. The scene owns all
 * its arrays; rt_scene_free() releases them. Lengths are in scene units, angles in degrees only
 * where a field says so.
 */
#ifndef RENDER_SCENE_H
#define RENDER_SCENE_H

#include <stddef.h>

#include "core/types.h"

#define RT_NAME_MAX 48

/** The refractive indices a scene's "ior" (a number, or a model over 380..780 nm) and the
 *  command line's --n1, --n2 may take. Real media lie between about 0.05 (silver's real part in
 *  the visible) and 4 (germanium in the infrared); [1e-3, 100] holds them all with room to
 *  spare, and keeps every index a normal double whose ratios and products with another stay far
 *  from underflow and overflow (an index of 1e-323, subnormal, kept 3 significant bits). */
#define RT_IOR_MIN 1e-3
#define RT_IOR_MAX 100.0

/** Surface optics (textbook 9.1): I = ka Ia C + sum_l S_l I_l (kd C max(0, N.L) + ks (R.V)^phong)
 *  + kr I_r + kt T I_t, with C = color, T = transmittance, S_l the shadow transmittance. */
typedef struct {
  char name[RT_NAME_MAX]; /**< name used by scene files and diagnostics */
  rt_rgb_t color;         /**< surface colour, multiplies the ambient and diffuse terms */
  double ka;              /**< ambient coefficient */
  double kd;              /**< diffuse coefficient */
  double ks;              /**< specular (Phong) coefficient */
  double phong;           /**< Phong exponent, >= 0 */
  double kr;              /**< coherent reflection coefficient */
  double kt;        /**< coherent refraction coefficient; > 0 makes the material transparent */
  double ior;       /**< refractive index of the material's interior, RT_IOR_MIN..RT_IOR_MAX (at
                         the d-line when the index is a model) */
  px_index_t index; /**< the index as a function of wavelength (paraxial/dispersion.h): constant
                         (ior) unless the scene gives a model (rt_scene_add_material() sets a
                         model that does not vary to ior); renderers use ior until dispersion
                         is drawn (issue 22) */
  int fresnel;      /**< 1: split kt between reflection (kt F) and refraction (kt (1 - F))
                         with the unpolarised Fresnel reflectance F; 0: constant kr, kt */
  rt_rgb_t transmittance; /**< colour filter of transmitted light (refraction and shadow rays) */
} rt_material_t;

/** Opaque, matte white: ka 0.1, kd 0.9, no specular, reflection or refraction, ior 1. */
rt_material_t rt_material_default(const char *name);

typedef enum {
  RT_OBJ_SPHERE = 0,
  RT_OBJ_PLANE = 1,     /**< infinite plane, optionally checkered */
  RT_OBJ_POLYGON = 2,   /**< one planar polygon (open surface) */
  RT_OBJ_POLYHEDRON = 3 /**< closed, consistently oriented polygon mesh, convex or not */
} rt_object_kind_t;

typedef struct {
  rt_object_kind_t kind;
  char name[RT_NAME_MAX]; /**< optional name, "" when none */
  int material;           /**< material index */
  int material2;          /**< checkerboard: material of the odd squares, or -1 (planes only) */
  int closed;             /**< 1 when the object bounds a volume (sphere, polyhedron) */
  int alone;      /**< set by rt_scene_prepare(): 1 when the object is closed and convex (a sphere,
                       or a polyhedron of at most 1,024 faces) and no other primitive meets its
                       bounding box, so that a ray inside it meets its own surface before anything
                       else, once */
  int first_prim; /**< its primitives are prim[first_prim .. first_prim + nprim - 1] */
  int nprim;
} rt_object_t;

typedef enum { RT_PRIM_SPHERE = 0, RT_PRIM_PLANE = 1, RT_PRIM_POLYGON = 2 } rt_prim_kind_t;

typedef struct {
  px_vec3_t c; /**< centre */
  double r;    /**< radius, > 0 */
} rt_sphere_t;

typedef struct {
  px_vec3_t p;      /**< a point of the plane; origin of the texture coordinates */
  px_vec3_t n;      /**< unit normal */
  px_vec3_t u;      /**< unit texture axis in the plane */
  px_vec3_t v;      /**< second texture axis, v = n x u */
  double check;     /**< checker square size, > 0 with a finite 1 / check (also when the plane is
                         not checkered) */
  double inv_check; /**< 1 / check: square indices are floor(u * inv_check), a multiplication,
                         because a division per lookup showed in the exact renderer's profile
                         (docs/tuning.md) */
} rt_plane_t;

typedef struct {
  px_vec3_t n; /**< unit normal; for polyhedra outward */
  double d;    /**< plane offset: n . x = d */
  int first;   /**< vertices vertex[first .. first + count - 1], in order */
  int count;   /**< >= 3 */
  int axis;    /**< coordinate dropped for the 2-D inside test: the largest |n| component */
} rt_polygon_t;

typedef struct {
  rt_prim_kind_t kind;
  int object; /**< owning object */
  union {
    rt_sphere_t sphere;
    rt_plane_t plane;
    rt_polygon_t polygon;
  };
} rt_prim_t;

typedef enum {
  RT_LIGHT_POINT = 0,
  RT_LIGHT_PARALLEL = 1,
  RT_LIGHT_AREA = 2 /**< a Lambertian rectangle (1989 paper, section 2.3) */
} rt_light_kind_t;

/** A scene's wish for caustics: light that reaches diffuse surfaces through reflecting or
 *  transparent objects, drawn from illuminance maps (issue 25) instead of the textbook's straight
 *  shadow rays attenuated by kt. */
typedef enum {
  RT_CAUSTICS_AUTO = 0, /**< where the effects plan finds such light (the default) */
  RT_CAUSTICS_OFF = 1 /**< never: the textbook's shadows (the paper's Fig. 8 is a Whitted image) */
} rt_caustics_t;

/** How a point light's intensity falls off with distance in rendering. */
typedef enum {
  RT_FALLOFF_NONE = 0,          /**< the textbook's model: `intensity` at any distance */
  RT_FALLOFF_INVERSE_SQUARE = 1 /**< physical: intensity / r^2, as the illuminance maps have it */
} rt_falloff_t;

/** A light. By default no distance fall-off (the textbook's model): a point light delivers
 *  `intensity` at any distance; a parallel light arrives everywhere from one direction. A point
 *  light may ask for the physical inverse-square fall-off instead. */
typedef struct {
  rt_light_kind_t kind;
  px_vec3_t v;          /**< point: position; parallel: unit direction the light travels in;
                             area: the rectangle's centre */
  rt_rgb_t intensity;   /**< I_l (at unit distance with inverse-square fall-off); area: the whole
                             rectangle's intensity along its normal, I0 (I0 cos(theta) at angle
                             theta from it: a Lambertian emitter of radiance I0 / area) */
  rt_falloff_t falloff; /**< RT_FALLOFF_NONE for a parallel light; an area light's is always
                             RT_FALLOFF_INVERSE_SQUARE */
  px_vec3_t eu, ev;     /**< area: the rectangle's two edges (centre +- eu / 2 +- ev / 2); it
                             emits on the side of eu x ev. Zero for the other kinds */
  int samples;          /**< area: the side N of its mesh, N x N Lambertian points at the mesh
                             cells' centres, each with I0 / N^2 (shading's direct light and soft
                             shadows, and its caustic maps; 1..RT_MAX_AREA_SAMPLES); 0 for the
                             other kinds */
} rt_light_t;

/** Largest side of an area light's mesh of sample points. */
#define RT_MAX_AREA_SAMPLES 64

/** The default side of an area light's mesh (the 1989 paper's Fig. 10: 7). */
#define RT_AREA_SAMPLES_DEFAULT 8

/** Pinhole camera. Pixel (i, j) covers [i, i+1) x [j, j+1) in continuous pixel coordinates,
 *  i counting columns from the left and j rows from the top. */
typedef struct {
  px_vec3_t eye;     /**< pinhole position */
  px_vec3_t look_at; /**< point imaged at the image centre */
  px_vec3_t up;      /**< approximate up direction, not parallel to look_at - eye */
  double fov_deg;    /**< full vertical field of view, degrees, in (0, 180) */
  int width;         /**< pixels, >= 1 */
  int height;        /**< pixels, >= 1 */
} rt_camera_t;

/** Sub-pixel grids: s x s samples per pixel with s = 1..RT_MAX_SPP_SIDE (1, 4, ..., 1024). The
 *  paper's Fig. 9 goes to 49 (s = 7); larger grids extend it (issue 26's curves to 1024). */
#define RT_MAX_SPP_SIDE 32
#define RT_MAX_SPP (RT_MAX_SPP_SIDE * RT_MAX_SPP_SIDE)

/** Wavelength bins of a spectral fan (scene setting "spectral_bins"): 4..RT_MAX_BINS, default
 *  RT_DEFAULT_BINS (docs/spectral.md). */
#define RT_MIN_BINS 4
#define RT_MAX_BINS 400
#define RT_DEFAULT_BINS 40

struct rt_bvh;

/** The cross-screen (star) filter a scene asks for (`"post": {"star": {...}}`, docs/star.md; the
 *  1989 paper's section 4): the scratched plate and the camera of post/star.h's pp_star_t, and
 *  the display curve of the preview. Applied to the image after rendering; off unless asked. */
typedef struct {
  int on;
  int directions;
  double angle_deg, ratio, sigma1, sigma2, weight2, ior, focal_mm, frame_mm;
  double exposure, white; /**< the preview's display curve (pp_tone()) */
} rt_star_t;

typedef struct {
  rt_camera_t camera;
  rt_rgb_t ambient;    /**< Ia, the global ambient intensity */
  rt_rgb_t background; /**< radiance of rays that meet nothing */
  int max_depth;       /**< reflection/refraction generations after the primary ray, >= 0 */
  int spp;             /**< default samples per pixel (s x s, s = 1..RT_MAX_SPP_SIDE) */
  int shadows;         /**< 0 disables shadow rays (every light always reaches every point) */
  double ior;          /**< refractive index of the space between objects */
  int caustics;        /**< rt_caustics_t: whether the scene wants light through specular and
                            transparent objects drawn as caustics */
  rt_star_t star;      /**< the star filter after rendering (star.on = 0: none) */
  int spectral_bins;   /**< wavelength bins over 380-780 nm where a white ray refracts into a
                            dispersive material (RT_EFFECT_DISPERSION), 4..RT_MAX_BINS */

  rt_material_t *material;
  int nmaterial, cap_material;
  rt_object_t *object;
  int nobject, cap_object;
  rt_prim_t *prim;
  int nprim, cap_prim;
  px_vec3_t *vertex; /**< polygon vertices */
  int nvertex, cap_vertex;
  rt_light_t *light;
  int nlight, cap_light;

  struct rt_bvh *bvh; /**< built by rt_scene_prepare(); NULL before */
  int *unbounded;     /**< primitives outside the BVH (planes) */
  int nunbounded;
} rt_scene_t;

/** An empty scene with default settings: camera at (0, 0, -5) looking at the origin, 40 degree
 *  field, 64 x 64; ambient 0.1, black background, depth 5, 1 spp, shadows on, ior 1. */
void rt_scene_init(rt_scene_t *s);
/** Release everything the scene owns and leave it empty (as after rt_scene_init()). */
void rt_scene_free(rt_scene_t *s);

/** Append a material (copied); its index in *index (may be NULL). */
rt_status_t rt_scene_add_material(rt_scene_t *s, const rt_material_t *m, int *index);
/** Index of the material called `name`, or -1. */
int rt_scene_find_material(const rt_scene_t *s, const char *name);

/** Sphere |p - c| = r, r > 0. Object index in *object (may be NULL). */
rt_status_t rt_scene_add_sphere(rt_scene_t *s, px_vec3_t c, double r, int material, int *object);
/** Infinite plane through p with normal n. `u_hint` is projected into the plane to give the
 *  texture axis u (a fixed axis when it is parallel to n). material2 >= 0 makes a checkerboard
 *  of squares of side `check`: square (floor(u/check), floor(v/check)) with an odd coordinate
 *  sum uses material2. */
rt_status_t rt_scene_add_plane(rt_scene_t *s, px_vec3_t p, px_vec3_t n, px_vec3_t u_hint,
                               int material, int material2, double check, int *object);
/** One planar polygon (convex or not, not self-intersecting) with n >= 3 vertices in order;
 *  its normal follows the right-hand rule. RT_EGEOMETRY when it is degenerate or a vertex lies
 *  farther than 1e-9 (relative to its size) from its plane. */
rt_status_t rt_scene_add_polygon(rt_scene_t *s, const px_vec3_t *v, int n, int material,
                                 int *object);
/** Closed polyhedron: nv vertices, nface faces; face f has face_len[f] vertex indices starting
 *  at face_idx[sum of earlier lengths]. Every edge must be shared by exactly two faces that
 *  traverse it in opposite directions; the faces are then oriented outwards (by the sign of the
 *  enclosed volume). On RT_EGEOMETRY / RT_EINVAL a reason is written to why[cap] when why is
 *  not NULL, and the scene is unchanged. */
rt_status_t rt_scene_add_polyhedron(rt_scene_t *s, const px_vec3_t *v, int nv, const int *face_idx,
                                    const int *face_len, int nface, int material, int *object,
                                    char *why, size_t cap);
/** Append a light (a parallel light's direction normalised; an area light's fall-off set to the
 *  inverse square). RT_EINVAL for a non-finite position, direction, edge or intensity, a zero
 *  direction, a fall-off on a parallel light, or an area light whose edges span no area. */
rt_status_t rt_scene_add_light(rt_scene_t *s, const rt_light_t *l);

/** Name an object (truncated to RT_NAME_MAX - 1 characters). */
void rt_scene_name_object(rt_scene_t *s, int object, const char *name);

/** Check the settings (camera, depth, spp, indices) and build the BVH. Must be called after the
 *  last change and before tracing. RT_EINVAL for bad settings, RT_ENOMEM. */
rt_status_t rt_scene_prepare(rt_scene_t *s);
/** Whether polyhedron o is convex: every vertex of it on the inner side of every face's plane,
 *  within 1e-9 of `size` (the object's; the faces' normals are outward). O(faces x vertices). */
int rt_polyhedron_convex(const rt_scene_t *s, const rt_object_t *o, double size);

/** 1 when the Fig. 10 error measure counts hits on `object` (>= 0): its material, or either
 *  material of a checkerboard, has a diffuse term (kd > 0). The paper measures on the
 *  checkerboard; in Fig. 8 that is the only such surface (the glass has kd = 0), and in a scene
 *  without a checkerboard (Fig. 11's rectangle) the measure still has points to compare. Shared
 *  by every renderer that measures (pencil, beam). */
static inline int rt_object_measured(const rt_scene_t *s, int object) {
  const rt_object_t *o = &s->object[object];
  return s->material[o->material].kd > 0.0 ||
         (o->material2 >= 0 && s->material[o->material2].kd > 0.0);
}

/** rt_scene_material_at() for a checkerboard (o->material2 >= 0): scene.c. */
const rt_material_t *rt__scene_checker_at(const rt_scene_t *s, const rt_object_t *o, int prim,
                                          px_vec3_t p, int *texel);

/** Material of primitive `prim` at point p: the object's material, or material2 on the odd
 *  squares of a checkerboard. *texel (may be NULL) gets the square's parity (0 or 1), or -1
 *  when the object has no texture. Inline: shading looks it up at every hit, and an object
 *  without texture needs no more than two loads. */
static inline const rt_material_t *rt_scene_material_at(const rt_scene_t *s, int prim, px_vec3_t p,
                                                        int *texel) {
  const rt_object_t *o = &s->object[s->prim[prim].object];
  if (o->material2 >= 0)
    return rt__scene_checker_at(s, o, prim, p, texel);
  if (texel)
    *texel = -1;
  return &s->material[o->material];
}

/** Plane texture coordinates (u, v) of p, in scene units from the plane's point. */
void rt_plane_coords(const rt_plane_t *pl, px_vec3_t p, double *u, double *v);

#endif
