/* cascade.h -- optical systems in cascade, T = Tn ... T1 (section 2.1 "System matrix"; the
 * partial products T_i^a, T_i^b of the Appendix (3)).
 *
 * A cascade keeps its element list, so that the error analysis can revisit each element and
 * the partial products before and after it. Storage is caller-owned: px_cascade_init() takes
 * an array and its capacity, and nothing is allocated.
 */
#ifndef PARAXIAL_CASCADE_H
#define PARAXIAL_CASCADE_H

#include <stddef.h>

#include "paraxial/system.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  PX_ELEMENT_TRANSFER = 0, /**< propagation in a homogeneous medium, Eq. (1) */
  PX_ELEMENT_REFRACT = 1,  /**< refraction at a smooth surface, Eq. (2) */
  PX_ELEMENT_REFLECT = 2   /**< reflection at a smooth surface, section 2.2 (3) */
} px_element_kind_t;

/** One element system with the data its error coefficients need. */
typedef struct {
  px_element_kind_t kind; /**< what the element is */
  px_mat4_t t;            /**< its system matrix */
  double distance;        /**< transfer length (TRANSFER only) */
  px_interface_t ifc;     /**< surface geometry (REFRACT / REFLECT only) */
  px_frame_t in, out;     /**< ray frames before and after the element */
} px_element_t;

typedef struct {
  px_element_t *elem; /**< caller-owned array, elem[0] acts first */
  size_t n;           /**< number of elements in use */
  size_t cap;         /**< capacity of elem */
} px_cascade_t;

/** Use `storage` (cap elements) for a new, empty cascade. */
void px_cascade_init(px_cascade_t *c, px_element_t *storage, size_t cap);

/** Append a transfer of length d (d may be negative: a virtual backward transfer). */
px_status_t px_cascade_push_transfer(px_cascade_t *c, double d, px_frame_t frame);

/** Append a refraction or reflection in the given frames (see px_interface_matrix). */
px_status_t px_cascade_push_interface(px_cascade_t *c, const px_interface_t *ifc, px_event_t ev,
                                      px_frame_t in, px_frame_t out, px_variant_t variant);

/** T = Tn ... T1 (identity for an empty cascade). */
px_mat4_t px_cascade_product(const px_cascade_t *c);

/** |Tn| ... |T1|, the product of the elements' entrywise absolute values: it bounds the
 *  rounding of each entry of the product (|fl(T) - T| <= gamma |Tn| ... |T1|), which is large
 *  against |T| where terms cancel (a receiver near a caustic; px_spread_ratio()). */
px_mat4_t px_cascade_product_abs(const px_cascade_t *c);

/** T_i^a = Tn ... T(i+1) (identity for i = n) with i 1-based as in the Appendix. */
px_mat4_t px_cascade_after(const px_cascade_t *c, size_t i);

/** T_i^b = T(i-1) ... T1 (identity for i = 1) with i 1-based as in the Appendix. */
px_mat4_t px_cascade_before(const px_cascade_t *c, size_t i);

#ifdef __cplusplus
}
#endif

#endif
