/* version.c -- px_version(): the version this library was built as (paraxial/version.h). */
#include "paraxial/version.h"

const char *px_version(void) {
  return PX_VERSION_STRING;
}
