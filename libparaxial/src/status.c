/* status.c -- messages for px_status_t. */
#include "paraxial/status.h"

const char *px_strerror(px_status_t status) {
  switch (status) {
  case PX_OK:
    return "success";
  case PX_EINVAL:
    return "invalid parameter";
  case PX_ETIR:
    return "total internal reflection: no refracted ray exists";
  case PX_EGRAZING:
    return "grazing incidence or exit: cos(theta) or cos(theta') is too small";
  case PX_ESINGULAR:
    return "singular matrix or degenerate frame";
  case PX_EMISS:
    return "the ray misses the surface";
  case PX_ECAPACITY:
    return "caller-owned buffer is full";
  case PX_ENONFINITE:
    return "result is not finite (overflow)";
  case PX_ENOCONVERGE:
    return "iteration did not converge";
  case PX_EILLCOND:
    return "too ill-conditioned: double precision cannot give the result to the stated accuracy";
  case PX_ECAUSTIC:
    return "at or too near a caustic: the pencil's cross-section vanishes";
  }
  return "unknown status";
}

const char *px_status_name(px_status_t status) {
  static const char *const names[] = {
      "PX_OK",        "PX_EINVAL",     "PX_ETIR",        "PX_EGRAZING", "PX_ESINGULAR", "PX_EMISS",
      "PX_ECAPACITY", "PX_ENONFINITE", "PX_ENOCONVERGE", "PX_EILLCOND", "PX_ECAUSTIC"};
  return (unsigned)status < sizeof names / sizeof names[0] ? names[status] : "PX_EUNKNOWN";
}
