/* ball_lens.c -- a program using the installed libparaxial: the system matrix of a glass ball
 * traversed along a diameter (two refractions and a transfer in cascade, Eqs. 1-2 of Shinya,
 * Takahashi and Naito 1987), checked against the ball lens's focal length, and a single oblique
 * refraction. Exits 1 when a check fails.
 *
 * Build: see README.md (CMake: find_package(paraxial); or pkg-config --cflags --libs paraxial). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <paraxial/paraxial.h>

static void print_matrix(const char *title, px_mat4_t t) {
  printf("%s\n", title);
  for (int r = 0; r < 4; r++)
    printf("  %10.6f %10.6f %10.6f %10.6f\n", t.m[r][0] + 0.0, t.m[r][1] + 0.0, t.m[r][2] + 0.0,
           t.m[r][3] + 0.0); /* + 0.0: no "-0.000000" */
}

/* Append the refraction at a sphere of radius r met at normal incidence, n1 -> n2. */
static px_status_t push_refraction(px_cascade_t *c, double r, double n1, double n2,
                                   px_frame_t *out) {
  px_interface_t ifc;
  px_frame_t in;
  px_status_t st = px_interface_canonical(0.0, r, n1, n2, &ifc);
  if (st == PX_OK)
    st = px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, out);
  if (st == PX_OK)
    st = px_cascade_push_interface(c, &ifc, PX_EVENT_REFRACT, in, *out, PX_VARIANT_CORRECTED);
  return st;
}

int main(void) {
  int fail = 0;
  printf("libparaxial %s (headers %s)\n", px_version(), PX_VERSION_STRING);
  if (strcmp(px_version(), PX_VERSION_STRING) != 0) {
    fprintf(stderr, "ball_lens: library %s does not match headers %s\n", px_version(),
            PX_VERSION_STRING);
    fail = 1;
  }

  /* A ball of radius R and index n in air: enter (centre beyond the surface, +R), cross the
   * diameter, leave (centre behind, -R). */
  const double radius = 1.0, n = 1.5, pi = 3.14159265358979323846;
  px_element_t storage[3];
  px_cascade_t ball;
  px_frame_t frame;
  px_cascade_init(&ball, storage, 3);
  px_status_t st = push_refraction(&ball, radius, 1.0, n, &frame);
  if (st == PX_OK)
    st = px_cascade_push_transfer(&ball, 2.0 * radius, frame);
  if (st == PX_OK)
    st = push_refraction(&ball, -radius, n, 1.0, &frame);
  if (st != PX_OK) {
    fprintf(stderr, "ball_lens: %s\n", px_strerror(st));
    return 1;
  }
  px_mat4_t t = px_cascade_product(&ball);
  print_matrix("ball lens, R = 1, n = 1.5, along a diameter:", t);
  /* A ball lens has focal length f = n R / (2 (n - 1)) from its centre: C = -I / f. */
  double f = n * radius / (2.0 * (n - 1.0));
  for (int i = 0; i < 2; i++)
    if (fabs(t.m[2 + i][i] + 1.0 / f) > 1e-12) {
      fprintf(stderr, "ball_lens: C[%d][%d] = %.17g, expected %.17g\n", i, i, t.m[2 + i][i],
              -1.0 / f);
      fail = 1;
    }

  px_mat4_t r30;
  st = px_element_matrix(PX_EVENT_REFRACT, 30.0 * pi / 180.0, 1.0, n, 2.0, PX_VARIANT_CORRECTED,
                         &r30);
  if (st != PX_OK) {
    fprintf(stderr, "ball_lens: %s\n", px_strerror(st));
    return 1;
  }
  print_matrix("refraction at 30 degrees, R = 2, n 1 -> 1.5:", r30);

  /* the header's inline vector functions (libm in the program): |(3, 4, 12)| = 13 */
  if (px_v3_norm(px_v3(3.0, 4.0, 12.0)) != 13.0) {
    fprintf(stderr, "ball_lens: px_v3_norm\n");
    fail = 1;
  }
  return fail;
}
