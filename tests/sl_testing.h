/* A minimal test harness: checks count failures, the main function returns their number and
 * prints the plain closing line 'N passed, N failed'. */
#ifndef SL_TESTING_H
#define SL_TESTING_H

#include <stdio.h>

typedef struct sl_test_state {
  int passed, failed;
} sl_test_state;

extern sl_test_state sl_tests;

/* Relative-or-absolute closeness: |a-b| <= atol + rtol*|b|. */
int sl_check_close(const char *file, int line, const char *what, double got, double want, double rtol,
                   double atol);
int sl_check_true(const char *file, int line, const char *what, int ok);
int sl_test_finish(const char *suite);

#define CHECK(cond) sl_check_true(__FILE__, __LINE__, #cond, (cond))
#define CHECK_MSG(cond, what) sl_check_true(__FILE__, __LINE__, (what), (cond))
#define CHECK_CLOSE(got, want, rtol, atol) sl_check_close(__FILE__, __LINE__, #got, (got), (want), (rtol), (atol))

#endif
