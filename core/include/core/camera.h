/* camera.h -- the pinhole camera: primary rays through continuous pixel coordinates (course
 * notes 1.7.2: "the pixel must be mapped to a ray in space"). */
#ifndef RENDER_CAMERA_H
#define RENDER_CAMERA_H

#include "core/scene.h"

/** The camera's orthonormal frame and image-plane scale, computed once. */
typedef struct {
  px_vec3_t eye;
  px_vec3_t right;   /**< image +x (towards larger pixel column i) */
  px_vec3_t down;    /**< image +y (towards larger pixel row j) */
  px_vec3_t forward; /**< viewing direction */
  double half_h;     /**< tan(fov/2): half height of the image plane at distance 1 */
  double half_w;     /**< half_h * width / height */
  int width, height;
} rt_view_t;

/** Frame for a camera; RT_EINVAL when eye == look_at, up is parallel to the view, the field
 *  of view is outside (0, 180) degrees or the size is not positive. */
rt_status_t rt_view_make(const rt_camera_t *cam, rt_view_t *out);

/** Primary ray through continuous pixel coordinates (x, y): x in [0, width) from the left,
 *  y in [0, height) from the top; pixel (i, j) has its centre at (i + 0.5, j + 0.5). */
rt_ray_t rt_view_ray(const rt_view_t *v, double x, double y, double ior);

#endif
