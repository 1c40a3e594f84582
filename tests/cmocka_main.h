/* cmocka_main.h -- includes and assertions shared by the cmocka test programs. Each program ends
 * with the same main(): an optional argument filters one case by name, so that every case is
 * its own ctest entry (tests/CMakeLists.txt finds the names in the source). */
#ifndef PENCIL_TESTS_CMOCKA_MAIN_H
#define PENCIL_TESTS_CMOCKA_MAIN_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* |a - b| <= rtol * max(|a|, |b|) + atol */
#define assert_close(a, b, rtol, atol)                                                             \
  do {                                                                                             \
    double a_ = (a), b_ = (b);                                                                     \
    double m_ = fabs(a_) > fabs(b_) ? fabs(a_) : fabs(b_);                                         \
    if (!(fabs(a_ - b_) <= (rtol)*m_ + (atol)))                                                    \
      fail_msg("%s = %.17g vs %s = %.17g (rtol %g, atol %g)", #a, a_, #b, b_, (double)(rtol),      \
               (double)(atol));                                                                    \
  } while (0)

#endif
