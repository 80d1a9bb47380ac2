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

#endif
