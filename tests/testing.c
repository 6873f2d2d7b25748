#include "sl_testing.h"

#include <math.h>

sl_test_state sl_tests;

int sl_check_true(const char *file, int line, const char *what, int ok)
{
  if (ok) {
    sl_tests.passed++;
  } else {
    sl_tests.failed++;
    fprintf(stderr, "%s:%d: FAILED: %s\n", file, line, what);
  }
  return ok;
}

int sl_check_close(const char *file, int line, const char *what, double got, double want, double rtol,
                   double atol)
{
  const int ok = isfinite(got) && fabs(got - want) <= atol + rtol * fabs(want);
  if (!ok) {
    fprintf(stderr, "%s:%d: FAILED: %s = %.17g, want %.17g (rtol %g, atol %g)\n", file, line, what, got, want,
            rtol, atol);
  }
  return sl_check_true(file, line, what, ok);
}

int sl_test_finish(const char *suite)
{
  printf("%s: %d passed, %d failed\n", suite, sl_tests.passed, sl_tests.failed);
  return sl_tests.failed ? 1 : 0;
}
