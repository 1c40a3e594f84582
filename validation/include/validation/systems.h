/* systems.h -- the verification sweep: a deterministic list of optical systems (single
 * refractions and reflections on planes, spheres both ways round, cylinders at any orientation
 * and ellipsoids, in paper frames and in rotated frames; transfers; cascades such as
 * pinhole -> glass sphere -> plane), each an ex_system_t the exact tracer can run. */
#ifndef VALIDATION_SYSTEMS_H
#define VALIDATION_SYSTEMS_H

#include <stddef.h>

#include "exact/trace.h"

typedef enum {
  VAL_FAMILY_TRANSFER,
  VAL_FAMILY_PLANE,
  VAL_FAMILY_SPHERE,
  VAL_FAMILY_CYLINDER,
  VAL_FAMILY_ELLIPSOID,
  VAL_FAMILY_CASCADE,
  VAL_FAMILY_COUNT
} val_family_t;

typedef struct {
  char label[112];                  /**< what the system is, for tables */
  val_family_t family;              /**< which family of the sweep */
  px_event_t event;                 /**< single elements: refraction or reflection */
  double theta_deg, n1, n2, radius; /**< single elements: parameters (radius Inf = plane) */
  int rotated;                      /**< frames rotated about the rays (non-diagonal Theta) */
  int expect_tir;                   /**< the axial ray is totally reflected: no matrix exists */
  double length;                    /**< length scale L of the system (docs/verification.md) */
  ex_stage_t stage[EX_MAX_STAGES];  /**< the stages; bind with val_system_bind() */
  ex_system_t sys;                  /**< the system; sys.stage is set by val_system_bind() */
} val_system_t;

const char *val_family_name(val_family_t f);

/** Build the sweep into a newly allocated array (free with free()); `scale` >= 1 repeats the
 *  randomised families that many times (the default sweep, scale 1, has > 2,000 systems);
 *  `quick` keeps a small subset for tests. Returns NULL on allocation failure. */
val_system_t *val_sweep_build(int scale, int quick, size_t *count);

/** The system with its stage pointer aimed at v->stage (call after copying a val_system_t). */
ex_system_t val_system_bind(const val_system_t *v);

#endif
