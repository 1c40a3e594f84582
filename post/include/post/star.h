/* star.h -- the cross-screen (star) filter of the 1989 paper (Shinya, Saito, Takahashi, Graphics
 * Interface 1989), section 4: a camera filter made of a glass plate with grid-like scratches
 * turns every bright point of an image into a star, and since the plate sits in front of an ideal
 * lens, the star is the same for every point: the image is linearly filtered.
 *
 * The plate's front-face normals follow f(N) = A delta(N) + B f0(N), A + B = 1 (section 4.2), B
 * the scratched share of its area. A parallel bundle along the axis is refracted by a front face
 * of normal N and by the flat back face, and the lens of focal length d images it at
 * (x, y) = (n - 1) d (N_x, N_y) (the thin-prism linearisation of Snell's law, section 4.1), so
 * that a point of the image becomes the illuminance of Eq. (16),
 *     E(x, y) = f(N) / ((n - 1) d)^2,   N = (x, y) / ((n - 1) d),
 * and the filtered image is I1 = I0 convolved with E (step 2; the printed integral's variables are
 * garbled, docs/errata.md).
 *
 * f0 here: the scratches run in `directions` directions, evenly spread over 180 degrees from
 * `angle_deg`; a scratch tilts the normal across itself only, so each direction contributes a
 * line of normals perpendicular to it, with a slope profile that is the paper's "sum of two
 * Gaussian functions": (1 - w2) N(0, sigma1) + w2 N(0, sigma2) (slopes in radians of tilt,
 * small). Each direction holds B / directions of the light. On the image a star ray is therefore
 * perpendicular to its scratches, and its profile is the slope profile stretched by
 * (n - 1) d / pitch pixels per unit slope, pitch = frame_mm / width (the sensor's pixel).
 *
 * The kernel is built on the pixel grid (pp_star_kernel()): the delta's A at the centre, each
 * line's profile integrated exactly over sub-pixel segments (erf) and spread bilinearly; its
 * radius is where the wider Gaussian's tail beyond it is below 1e-7, and each line is scaled to
 * hold exactly B / directions, so that the kernel sums to 1 (energy). The convolution is by FFT
 * (FFTW3, double precision) on a zero-padded grid large enough that nothing wraps around, so it
 * is the linear convolution; light a star carries beyond the frame is lost to the output and
 * reported (pp_star_flux_t). Angles are counter-clockwise on the displayed image (x right, y up).
 *
 * Prefix pp_. Pure image math on float planes: no files. */
#ifndef POST_STAR_H
#define POST_STAR_H

#include <stddef.h>

/** The plate and the camera. */
typedef struct {
  int directions;   /**< scratch directions, 1..16 (2: a grid, four star rays) */
  double angle_deg; /**< the first scratch direction's angle to the image's x axis, degrees */
  double ratio;     /**< B: the scratched share of the plate, [0, 1) (the paper: 0.07) */
  double sigma1;    /**< the narrow Gaussian's standard deviation of normal slope, > 0 */
  double sigma2;    /**< the wide Gaussian's, > 0 */
  double weight2;   /**< w2: the wide Gaussian's share of f0, [0, 1] */
  double ior;       /**< n of the plate, > 1 */
  double focal_mm;  /**< d: the lens's focal length (lens to image plane), mm, > 0 */
  double frame_mm;  /**< the image's width on the sensor, mm, > 0 (36: a 35 mm frame) */
} pp_star_t;

/** A grid plate (two directions at 45 degrees: an X-shaped star), B = 0.07 as the paper's
 *  Fig. 16, slopes of 0.02 and 0.1 radians in equal shares, glass of n = 1.5, a 50 mm lens on
 *  a 36 mm frame. */
#define PP_STAR_DEFAULT                                                                            \
  { 2, 45.0, 0.07, 0.02, 0.1, 0.5, 1.5, 50.0, 36.0 }

/** The kernel on the pixel grid: side x side values (side = 2 radius + 1), row-major, rows from
 *  the top of the image, the centre at (radius, radius); it sums to 1. */
typedef struct {
  int radius, side;
  double *k;
  double scale; /**< pixels per unit normal slope: (n - 1) d / pitch */
  double tail;  /**< the profile's mass beyond the radius, before the lines were scaled to B */
} pp_kernel_t;

/** Check p: 0, or -1 with the parameter at fault named in why[cap] ("ior must be > 1"). */
int pp_star_check(const pp_star_t *p, char *why, size_t cap);

/** The kernel of p for an image `width` pixels wide (which sets the pitch). -1 with the reason
 *  in why[cap] for a bad parameter, a kernel wider than max_side pixels (> 0; the caller's image,
 *  whose smaller side it must not exceed), or no memory. */
int pp_star_kernel(const pp_star_t *p, int width, int max_side, pp_kernel_t *k, char *why,
                   size_t cap);
void pp_kernel_free(pp_kernel_t *k);

/** The flux of one plane: what came in, what the full convolution holds (in the frame and beyond
 *  it: equal to the input's to rounding, the kernel summing to 1), what stayed in the frame, and
 *  the most negative value the FFT's rounding left (set to 0, reported against the plane's
 *  largest). */
typedef struct {
  double in, full, frame, clamped;
} pp_star_flux_t;

/** Filter the n planes in[c] (w x h floats, non-negative and finite: the caller checks) into
 *  out[c] (may be the same arrays) by the kernel: the linear convolution, by FFT on a grid of
 *  at least (w + radius) x (h + radius), pruned (only the image's rows and the rows it keeps are
 *  transformed along x). threads > 0 OpenMP threads (0: 1). flux may be NULL
 *  (else n entries). -1 with the reason in why[cap] when out of memory or FFTW cannot plan. */
int pp_star_apply(const pp_kernel_t *k, int w, int h, int n, const float *const *in, float **out,
                  int threads, pp_star_flux_t *flux, char *why, size_t cap);

/** The memory pp_star_apply() allocates for a w x h image and kernel k with `threads` threads
 *  (its threads argument): the half spectrum's rows, the kernel's spectrum and each thread's
 *  buffers, bytes. */
size_t pp_star_bytes(const pp_kernel_t *k, int w, int h, int threads);

/** The same convolution summed directly (O(w h side^2)): the FFT's check on small images. */
void pp_convolve_direct(const pp_kernel_t *k, int w, int h, const float *in, double *out);

/** The display transform phi of step 3): the extended Reinhard curve
 *  L' = L (1 + L / white^2) / (1 + L) on each channel after multiplying by `exposure`, which maps
 *  0 to 0 and `white` to 1 and compresses highlights smoothly (values above white clip), so that
 *  the stars' faint rays and the spots' cores both show on an 8-bit display. white > 0. */
float pp_tone(float linear, double exposure, double white);

#endif
