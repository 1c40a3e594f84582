/* camera.c -- the pinhole camera (course notes 1.7.2: each pixel is mapped to a ray from the eye
 * through the image plane; textbook 9.1: "for each pixel p, r = ray from the eye through p"). */
#include "core/camera.h"

#include <math.h>

#include "paraxial/vec3.h"

rt_status_t rt_view_make(const rt_camera_t *cam, rt_view_t *out) {
  rt_view_t v;
  if (!(cam->fov_deg > 0.0 && cam->fov_deg < 180.0) || cam->width < 1 || cam->height < 1)
    return RT_EINVAL;
  if (px_vec3_normalize(px_vec3_sub(cam->look_at, cam->eye), &v.forward) != PX_OK)
    return RT_EINVAL;
  /* right = forward x up: with a right-handed world this is the viewer's right */
  if (px_vec3_normalize(px_vec3_cross(v.forward, cam->up), &v.right) != PX_OK ||
      px_vec3_norm(px_vec3_cross(v.forward, cam->up)) < 1e-9 * px_vec3_norm(cam->up))
    return RT_EINVAL;
  v.down = px_vec3_cross(v.forward, v.right);
  v.eye = cam->eye;
  v.half_h = tan(0.5 * cam->fov_deg * M_PI / 180.0);
  v.half_w = v.half_h * cam->width / cam->height;
  v.width = cam->width;
  v.height = cam->height;
  *out = v;
  return RT_OK;
}

rt_ray_t rt_view_ray(const rt_view_t *v, double x, double y, double ior) {
  double sx = (2.0 * x / v->width - 1.0) * v->half_w;
  double sy = (2.0 * y / v->height - 1.0) * v->half_h;
  px_vec3_t d = px_v3_axpy(sx, v->right, px_v3_axpy(sy, v->down, v->forward));
  /* |d| >= 1: forward is unit and orthogonal to the offsets */
  return (rt_ray_t){v->eye, px_v3_unit(d), 0.0, INFINITY, ior, -1, 0.0f};
}
