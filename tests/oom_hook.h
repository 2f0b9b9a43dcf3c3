/* Allocation-failure injection for tests: the test executable replaces the
 * global C++ operator new/delete (tests/oom_hook.cpp). hgcd is linked
 * statically into the tests, so every allocation hgcd's C++ code makes goes
 * through these replacements; C code (the tests, cmocka, GMP, the OpenMP
 * runtime) allocates with malloc and is never failed. */
#ifndef HGCD_TESTS_OOM_HOOK_H
#define HGCD_TESTS_OOM_HOOK_H

#ifdef __cplusplus
extern "C" {
#endif

/* Makes the n-th (n >= 1) counted operator new from now on throw
 * std::bad_alloc (nothrow forms return NULL). sticky: every counted
 * allocation after it fails too, until oom_disarm (memory stays exhausted).
 * in_parallel: also count allocations made inside OpenMP parallel regions
 * (omp_get_level() > 0); by default those are never failed. */
void oom_arm(long n, int sticky, int in_parallel);
void oom_disarm(void);
/* 1 if an injected failure happened since the last oom_arm. */
int oom_tripped(void);
/* Counted allocations since the last oom_arm. */
long oom_counted(void);
/* Every operator new call since the start (all threads, counted or not). */
long oom_total_allocations(void);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_TESTS_OOM_HOOK_H */
