/* Wall time for the timings every renderer and tool reports: seconds on the monotonic clock
 * (never stepped by NTP), so differences are durations. */
#ifndef C5_CLOCK_H
#define C5_CLOCK_H

#include <time.h>

static inline double c5_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A cheaper clock for timing many short spans within a longer one: the time-stamp counter on
 * x86-64 (a few nanoseconds a read, against some 30 for c5_now_s), else nanoseconds. Ticks
 * are turned into seconds by timing the longer span both ways (c5_ticks_to_s). */
static inline unsigned long long c5_ticks(void)
{
#if defined(__x86_64__)
    return __builtin_ia32_rdtsc();
#else
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (unsigned long long)ts.tv_sec * 1000000000ull + (unsigned long long)ts.tv_nsec;
#endif
}

/* `ticks` in seconds, given that `span_ticks` ticks took `span_s` seconds. */
static inline double c5_ticks_to_s(unsigned long long ticks, unsigned long long span_ticks, double span_s)
{
    return span_ticks ? (double)ticks * span_s / (double)span_ticks : 0;
}

#endif
