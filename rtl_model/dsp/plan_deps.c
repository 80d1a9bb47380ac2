/* What each entry of the plan across boards waits for (plan_deps.h). */
#include <stdlib.h>

#include "plan_deps.h"

void c5_plan_deps(const int *parent, const int *cell, int n, const int *sched, int len, const uint16_t *owner,
                  int boards, int *dep)
{
    for (size_t i = 0; i < (size_t)len * (size_t)boards; i++)
        dep[i] = -1;
    int *at = malloc(sizeof *at * (size_t)(n > 0 ? n : 1)); /* the entry working off each node */
    if (!at)
        return;
    for (int v = 0; v < n; v++) {
        int from = parent[v] < 0 ? 0 : at[parent[v]] < 0 ? len : at[parent[v]] + 1;
        at[v] = -1;
        for (int i = from; i < len; i++)
            if (sched[i] == cell[v]) {
                at[v] = i;
                break;
            }
        int u = parent[v];
        if (u >= 0 && at[v] >= 0 && at[u] >= 0 && owner[cell[u]] != owner[cell[v]]) {
            int *d = &dep[(size_t)at[v] * (size_t)boards + owner[cell[u]]];
            if (*d < at[u])
                *d = at[u];
        }
    }
    free(at);
}
