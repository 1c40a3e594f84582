/* paraxial.h -- umbrella header of libparaxial, the pure math of pencil tracing
 * (Shinya, Takahashi, Naito, SIGGRAPH 1987). No I/O, no scene, no globals. */
#ifndef PARAXIAL_PARAXIAL_H
#define PARAXIAL_PARAXIAL_H

#include "paraxial/bounds.h"
#include "paraxial/cascade.h"
#include "paraxial/dispersion.h"
#include "paraxial/frame.h"
#include "paraxial/illuminance.h"
#include "paraxial/interp.h"
#include "paraxial/linalg.h"
#include "paraxial/polygon.h"
#include "paraxial/status.h"
#include "paraxial/system.h"
#include "paraxial/vec3.h"
#include "paraxial/version.h"

#endif
