/* bench_cholmod.c -- benchmark-only helper (not part of librebond): the symbolic analysis of
 * a 1-based upper-triangle pattern with the same CHOLMOD settings as src/linalg/cholmod_shim.c
 * (AMD and METIS tried, the one with less fill kept), to report nnz(L) and the flop count of
 * the factorization. The shim's factor is opaque, so the analysis is repeated here once. */
#include <stdlib.h>
#include "cholmod.h"

/* Returns 0 on success. lnz: nonzeros of L; xsize: entries stored (supernodal blocks);
 * fl: flops of the numeric factorization; ordering: 1 AMD, 2 METIS, other CHOLMOD code;
 * super: 1 if supernodal. */
int bench_chol_analyze(int n, int nnz, const int *colptr, const int *rowind,
                       double *lnz, double *xsize, double *fl, int *ordering, int *super)
{
    cholmod_common c;
    cholmod_sparse *A;
    cholmod_factor *L;
    int j, k;

    if (!cholmod_start(&c)) return 1;
    c.print = 0;
    c.final_ll = 1;
    c.nmethods = 2;
    c.method[0].ordering = CHOLMOD_AMD;
    c.method[1].ordering = CHOLMOD_METIS;
    A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nnz, 1, 1, 1, CHOLMOD_PATTERN, &c);
    if (A == NULL) {
        cholmod_finish(&c);
        return 2;
    }
    for (j = 0; j <= n; j++) ((int *)A->p)[j] = colptr[j] - 1;
    for (k = 0; k < nnz; k++) ((int *)A->i)[k] = rowind[k] - 1;
    L = cholmod_analyze(A, &c);
    if (L == NULL) {
        cholmod_free_sparse(&A, &c);
        cholmod_finish(&c);
        return 3;
    }
    *lnz = c.lnz;
    *fl = c.fl;
    *xsize = L->is_super ? (double)L->xsize : c.lnz;
    *super = L->is_super;
    *ordering = c.method[c.selected].ordering == CHOLMOD_AMD ? 1
              : c.method[c.selected].ordering == CHOLMOD_METIS ? 2 : 10 + c.method[c.selected].ordering;
    cholmod_free_factor(&L, &c);
    cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
    return 0;
}
