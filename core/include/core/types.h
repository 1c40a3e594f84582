/* types.h -- the small value types of the reference renderer: status codes, colours, rays and
 * ray-surface hits (textbook section 9.1: a ray is a half line, a hit is a single point).
 *
 * All are plain structs passed by value; nothing here allocates.
 */
#ifndef RENDER_TYPES_H
#define RENDER_TYPES_H

#include "paraxial/paraxial.h"

/** Result codes of the renderer. Static messages from rt_strerror(). */
typedef enum {
  RT_OK = 0,    /**< success */
  RT_ENOMEM,    /**< an allocation failed; nothing was changed */
  RT_EINVAL,    /**< a parameter is out of range or not finite */
  RT_EGEOMETRY, /**< degenerate geometry: a non-planar or zero-area polygon, an open polyhedron */
  RT_ENOTREADY, /**< the scene was changed after rt_scene_prepare() or never prepared */
  RT_ECAPACITY  /**< a caller-owned buffer is full */
} rt_status_t;

/** Static, human-readable message for a status; never NULL, thread-safe. */
const char *rt_strerror(rt_status_t s);

/** Linear RGB radiance or reflectance triple. */
typedef struct {
  double r, g, b;
} rt_rgb_t;

static inline rt_rgb_t rt_rgb(double r, double g, double b) {
  return (rt_rgb_t){r, g, b};
}
static inline rt_rgb_t rt_rgb_add(rt_rgb_t a, rt_rgb_t b) {
  return (rt_rgb_t){a.r + b.r, a.g + b.g, a.b + b.b};
}
static inline rt_rgb_t rt_rgb_mul(rt_rgb_t a, rt_rgb_t b) {
  return (rt_rgb_t){a.r * b.r, a.g * b.g, a.b * b.b};
}
static inline rt_rgb_t rt_rgb_scale(rt_rgb_t a, double s) {
  return (rt_rgb_t){a.r * s, a.g * s, a.b * s};
}
/** a + s * b */
static inline rt_rgb_t rt_rgb_madd(rt_rgb_t a, double s, rt_rgb_t b) {
  return (rt_rgb_t){a.r + s * b.r, a.g + s * b.g, a.b + s * b.b};
}
/** The largest component of a colour, which is finite (scene ranges, io/src/parse.h): a plain
 *  comparison, so no NaN test is paid per shadow query. */
static inline double rt_rgb_max(rt_rgb_t a) {
  double m = a.r > a.g ? a.r : a.g;
  return m > a.b ? m : a.b;
}

/** Kind of a ray in a ray tree (textbook Fig. 9.1: eye, reflected r, refracted t, shadow s). */
typedef enum {
  RT_RAY_PRIMARY = 0, /**< from the eye through the image plane */
  RT_RAY_REFLECT = 1, /**< coherent (mirror) reflection */
  RT_RAY_REFRACT = 2, /**< coherent refraction (Snell's law) */
  RT_RAY_SHADOW = 3   /**< towards a light source */
} rt_ray_kind_t;

/** A ray o + t d for t in [tmin, tmax], travelling in a medium of index `ior`. */
typedef struct {
  px_vec3_t o;   /**< origin, world coordinates */
  px_vec3_t d;   /**< direction, unit length */
  double tmin;   /**< nearest accepted distance (>= 0) */
  double tmax;   /**< farthest accepted distance (INFINITY for an unbounded ray) */
  double ior;    /**< refractive index of the medium the ray travels in (at `lambda` when the ray
                      is monochromatic) */
  int skip_prim; /**< planar primitive the ray leaves (it cannot meet it again), or -1 */
  float lambda;  /**< 0: a white (RGB) ray; else the wavelength, nm, of a monochromatic ray below
                      a spectral fan (core/src/shade.c; in the padding after skip_prim, so rays stay
                      80 bytes) */
} rt_ray_t;

/** The nearest surface point a ray meets. */
typedef struct {
  double t;    /**< distance along the ray (d is unit, so in length units) */
  px_vec3_t p; /**< hit point, world coordinates */
  px_vec3_t n; /**< unit geometric normal: outward for closed objects, as given for open ones */
  int prim;    /**< primitive index in the scene */
  int object;  /**< object index in the scene */
} rt_hit_t;

#endif
