/* The Cell Tree optimum as a time-indexed integer program through GLPK (tree_ilp.h). */
#include <glpk.h>
#include <stdlib.h>
#include <string.h>

#include "tree_ilp.h"

/* The constraint matrix, built row by row (GLPK's arrays count from 1). */
typedef struct {
    int *ia, *ja, nz, cap;
    double *ar;
} triplets;

static int put(triplets *m, int row, int col, double v)
{
    if (m->nz + 1 >= m->cap) {
        int cap = m->cap ? 2 * m->cap : 1024;
        int *ia = realloc(m->ia, sizeof *ia * (size_t)cap);
        if (ia)
            m->ia = ia;
        int *ja = realloc(m->ja, sizeof *ja * (size_t)cap);
        if (ja)
            m->ja = ja;
        double *ar = realloc(m->ar, sizeof *ar * (size_t)cap);
        if (ar)
            m->ar = ar;
        if (!ia || !ja || !ar)
            return -1;
        m->cap = cap;
    }
    m->nz++;
    m->ia[m->nz] = row;
    m->ja[m->nz] = col;
    m->ar[m->nz] = v;
    return 0;
}

int c5t_ilp_optimum(const c5_dep_tree *t, int horizon, int *len_out, int *sched)
{
    int n = t->n, T = horizon;
    if (n < 0)
        return -1;
    if (n == 0) {
        *len_out = 0;
        return 1;
    }
    if (T <= 0)
        return 0;
    /* The cells present, numbered 0..m-1. */
    static int index_of[C5_SCHED_MAX_CELLS];
    int ids[C5_SCHED_MAX_CELLS], m = 0;
    for (int c = 0; c < C5_SCHED_MAX_CELLS; c++)
        index_of[c] = -1;
    for (int v = 0; v < n; v++) {
        if (t->cell[v] < 0 || t->cell[v] >= C5_SCHED_MAX_CELLS)
            return -1;
        if (index_of[t->cell[v]] < 0) {
            index_of[t->cell[v]] = m;
            ids[m++] = t->cell[v];
        }
    }
    int *depth = malloc(sizeof *depth * (size_t)n);
    triplets mat = {0};
    glp_prob *lp = glp_create_prob();
    int rc = -1;
    if (!depth)
        goto done;
    /* Columns: y[k][t] = 1 + k*T + t, then x[v][t] = 1 + m*T + v*T + t. */
#define Y(k, s) (1 + (k) * T + (s))
#define X(v, s) (1 + m * T + (v) * T + (s))
    glp_set_obj_dir(lp, GLP_MIN);
    glp_add_cols(lp, (m + n) * T);
    for (int j = 1; j <= (m + n) * T; j++) {
        glp_set_col_kind(lp, j, GLP_BV);
        glp_set_obj_coef(lp, j, j <= m * T ? 1.0 : 0.0);
    }
    /* A node of depth d (1 for a root) needs d loads before and including its own. */
    for (int v = 0; v < n; v++) {
        depth[v] = t->parent[v] < 0 ? 1 : depth[t->parent[v]] + 1;
        for (int s = 0; s < T && s < depth[v] - 1; s++)
            glp_set_col_bnds(lp, X(v, s), GLP_FX, 0.0, 0.0);
    }
    int row = 0;
    /* One cell per position at most, and the used positions first (any schedule keeps its
     * order when its empty positions are dropped): symmetry the solver need not explore. */
    for (int s = 0; s < T; s++) {
        row = glp_add_rows(lp, 1);
        glp_set_row_bnds(lp, row, GLP_UP, 0.0, 1.0);
        for (int k = 0; k < m; k++)
            if (put(&mat, row, Y(k, s), 1.0))
                goto done;
        if (s + 1 < T) {
            row = glp_add_rows(lp, 1);
            glp_set_row_bnds(lp, row, GLP_LO, 0.0, 0.0);
            for (int k = 0; k < m; k++)
                if (put(&mat, row, Y(k, s), 1.0) || put(&mat, row, Y(k, s + 1), -1.0))
                    goto done;
        }
    }
    for (int v = 0; v < n; v++) {
        int k = index_of[t->cell[v]], p = t->parent[v];
        /* served exactly once */
        row = glp_add_rows(lp, 1);
        glp_set_row_bnds(lp, row, GLP_FX, 1.0, 1.0);
        for (int s = 0; s < T; s++)
            if (put(&mat, row, X(v, s), 1.0))
                goto done;
        for (int s = 0; s < T; s++) {
            /* by a load of its own cell */
            row = glp_add_rows(lp, 1);
            glp_set_row_bnds(lp, row, GLP_UP, 0.0, 0.0);
            if (put(&mat, row, X(v, s), 1.0) || put(&mat, row, Y(k, s), -1.0))
                goto done;
            /* served by position s only if the parent was served before s */
            if (p < 0)
                continue;
            row = glp_add_rows(lp, 1);
            glp_set_row_bnds(lp, row, GLP_UP, 0.0, 0.0);
            for (int r = 0; r <= s; r++)
                if (put(&mat, row, X(v, r), 1.0) || (r < s && put(&mat, row, X(p, r), -1.0)))
                    goto done;
        }
    }
    glp_load_matrix(lp, mat.nz, mat.ia, mat.ja, mat.ar);
    glp_iocp parm;
    glp_init_iocp(&parm);
    parm.presolve = GLP_ON;
    parm.msg_lev = GLP_MSG_OFF;
    int ret = glp_intopt(lp, &parm);
    if (ret == GLP_ENOPFS) { /* the presolver proved the program infeasible */
        rc = 0;
        goto done;
    }
    if (ret != 0)
        goto done;
    int st = glp_mip_status(lp);
    if (st == GLP_NOFEAS) {
        rc = 0;
        goto done;
    }
    if (st != GLP_OPT)
        goto done;
    int len = 0;
    for (int s = 0; s < T; s++)
        for (int k = 0; k < m; k++)
            if (glp_mip_col_val(lp, Y(k, s)) > 0.5) {
                if (sched)
                    sched[len] = ids[k];
                len++;
            }
    *len_out = len;
    rc = 1;
#undef Y
#undef X
done:
    glp_delete_prob(lp);
    free(mat.ia);
    free(mat.ja);
    free(mat.ar);
    free(depth);
    return rc;
}
