/* cholmod_shim.c -- a thin wrapper around CHOLMOD (int interface)
 * for one symmetric positive definite matrix stored as its upper triangle (stype = 1).
 *
 * Fortran sees an opaque handle (type(c_ptr)) to rb_chol, which owns the cholmod_common,
 * the matrix A (0-based copy of the 1-based Fortran pattern), the factor L and the dense
 * workspaces X/Y/E of cholmod_solve2. After the first solve a solve allocates nothing:
 * B is a header pointing at the caller's right-hand side, X/Y/E are reused by CHOLMOD.
 *
 * Return codes: RB_OK, RB_NOT_POSDEF (minor column set), RB_FAIL (CHOLMOD error),
 * RB_BADARG (caller error: sizes, pattern change, not factored). Messages are written,
 * NUL-terminated, into the caller's buffer msg[msglen]. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cholmod.h"

int rb_chol_solve(void *vh, int n, const double *b, double *x, char *msg, int msglen);

enum { RB_OK = 0, RB_NOT_POSDEF = 1, RB_FAIL = 2, RB_BADARG = 3 };

typedef struct {
    cholmod_common c;
    int started;          /* cholmod_start succeeded */
    cholmod_sparse *A;    /* pattern copied on the first factorization */
    cholmod_factor *L;    /* symbolic analysis kept across refactorizations */
    cholmod_dense B;      /* header only; x points at the caller's b during a solve */
    cholmod_dense *X, *Y, *E;
    int n, nnz;
    int factored;         /* L holds a valid numeric factorization of the current values */
} rb_chol;

/* Last message reported by CHOLMOD's error handler (the handler has no user pointer). */
static _Thread_local char last_msg[160];

static void rb_handler(int status, const char *file, int line, const char *message)
{
    (void)file;
    (void)line;
    snprintf(last_msg, sizeof last_msg, "%s (CHOLMOD status %d)", message ? message : "?", status);
}

static void set_msg(char *msg, int msglen, const char *text)
{
    if (msg == NULL || msglen <= 0) return;
    snprintf(msg, (size_t)msglen, "%s", text);
}

/* Message for a failed CHOLMOD call: what we were doing + CHOLMOD's own words. */
static int fail(rb_chol *h, char *msg, int msglen, const char *what)
{
    char buf[320];
    if (last_msg[0] != '\0')
        snprintf(buf, sizeof buf, "CHOLMOD %s failed: %s", what, last_msg);
    else
        snprintf(buf, sizeof buf, "CHOLMOD %s failed (status %d)", what, h->c.status);
    set_msg(msg, msglen, buf);
    return RB_FAIL;
}

void *rb_chol_new(void)
{
    rb_chol *h = calloc(1, sizeof *h);
    if (h == NULL) return NULL;
    if (!cholmod_start(&h->c)) {
        free(h);
        return NULL;
    }
    h->started = 1;
    h->c.print = 0;                /* no printing from the library: we report via stat */
    h->c.error_handler = rb_handler;
    /* LL' also in the simplicial case: an LDL' factorization would accept an indefinite
     * matrix (negative D) without complaint, and we must detect non-positive pivots. */
    h->c.final_ll = 1;
    /* Try AMD and METIS, keep the one with less fill: on 2D plates METIS cuts the fill and
     * the flop count of the factor (hence of every solve); the extra analysis is paid once. */
    h->c.nmethods = 2;
    h->c.method[0].ordering = CHOLMOD_AMD;
    h->c.method[1].ordering = CHOLMOD_METIS;
    return h;
}

void rb_chol_free(void *vh)
{
    rb_chol *h = vh;
    if (h == NULL) return;
    if (h->started) {
        cholmod_free_dense(&h->X, &h->c);
        cholmod_free_dense(&h->Y, &h->c);
        cholmod_free_dense(&h->E, &h->c);
        cholmod_free_factor(&h->L, &h->c);
        cholmod_free_sparse(&h->A, &h->c);
        cholmod_finish(&h->c);
    }
    free(h);
}

int rb_chol_is_factored(const void *vh)
{
    const rb_chol *h = vh;
    return h != NULL && h->factored;
}

void rb_chol_version(int *v)
{
    v[0] = CHOLMOD_MAIN_VERSION;
    v[1] = CHOLMOD_SUB_VERSION;
    v[2] = CHOLMOD_SUBSUB_VERSION;
}

/* First call: copy the 1-based pattern to A (0-based), analyze. Every call: copy the
 * values, numeric factorization. A later call must pass the same pattern. */
int rb_chol_factorize(void *vh, int n, int nnz, const int *colptr, const int *rowind,
                      const double *values, int *minor, char *msg, int msglen)
{
    rb_chol *h = vh;
    char buf[200];
    int j, k;

    *minor = 0;
    last_msg[0] = '\0';
    if (h == NULL) {
        set_msg(msg, msglen, "CHOLMOD factorize: null handle");
        return RB_BADARG;
    }

    if (h->A == NULL) {
        if (n < 1 || nnz < n || colptr[0] != 1 || colptr[n] != nnz + 1) {
            set_msg(msg, msglen, "CHOLMOD factorize: inconsistent pattern (n, nnz, colptr)");
            return RB_BADARG;
        }
        for (j = 0; j < n; j++) {
            if (colptr[j + 1] < colptr[j]) {
                set_msg(msg, msglen, "CHOLMOD factorize: colptr not monotone");
                return RB_BADARG;
            }
            for (k = colptr[j] - 1; k < colptr[j + 1] - 1; k++) {
                if (rowind[k] < 1 || rowind[k] > j + 1) {
                    snprintf(buf, sizeof buf, "CHOLMOD factorize: row %d in column %d is not in the "
                             "upper triangle", rowind[k], j + 1);
                    set_msg(msg, msglen, buf);
                    return RB_BADARG;
                }
            }
        }
        h->A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nnz, 1, 1, 1, CHOLMOD_REAL, &h->c);
        if (h->A == NULL) return fail(h, msg, msglen, "allocate_sparse");
        {
            int *Ap = h->A->p, *Ai = h->A->i;
            for (j = 0; j <= n; j++) Ap[j] = colptr[j] - 1;
            for (k = 0; k < nnz; k++) Ai[k] = rowind[k] - 1;
        }
        h->n = n;
        h->nnz = nnz;
    } else {
        const int *Ap = h->A->p, *Ai = h->A->i;
        int same = (n == h->n && nnz == h->nnz);
        for (j = 0; same && j <= n; j++) same = (Ap[j] == colptr[j] - 1);
        for (k = 0; same && k < nnz; k++) same = (Ai[k] == rowind[k] - 1);
        if (!same) {
            set_msg(msg, msglen, "CHOLMOD factorize: pattern differs from the one first factorized");
            return RB_BADARG;
        }
    }

    h->factored = 0;
    if (h->L == NULL) {
        /* A non-NULL L is a valid analysis even if one ordering method was unavailable
         * (e.g. a CHOLMOD built without METIS sets a negative status but keeps AMD's). */
        h->L = cholmod_analyze(h->A, &h->c);
        if (h->L == NULL) return fail(h, msg, msglen, "analyze");
    }

    memcpy(h->A->x, values, (size_t)nnz * sizeof(double));
    if (!cholmod_factorize(h->A, h->L, &h->c) || h->c.status < CHOLMOD_OK)
        return fail(h, msg, msglen, "factorize");

    if (h->c.status == CHOLMOD_NOT_POSDEF || h->L->minor < h->L->n) {
        /* L->minor indexes the permuted matrix P A P'; Perm maps it back to A's column. */
        size_t m = h->L->minor;
        int col = (int)m;
        if (h->L->Perm != NULL && m < h->L->n) col = ((const int *)h->L->Perm)[m];
        *minor = col + 1;
        snprintf(buf, sizeof buf, "matrix not positive definite: Cholesky pivot of column %d "
                 "(1-based) is not positive", col + 1);
        set_msg(msg, msglen, buf);
        return RB_NOT_POSDEF;
    }
    /* Other positive statuses (e.g. CHOLMOD_DSMALL, a tiny pivot) leave a usable factor. */
    h->factored = 1;
    if (h->X == NULL) {
        /* One solve of a zero right-hand side now, so that the solve workspaces X, Y, E exist
         * before any time loop: every later solve is allocation-free. */
        double *z = calloc(2 * (size_t)n, sizeof(double));
        int rc;
        if (z == NULL) {
            set_msg(msg, msglen, "CHOLMOD factorize: out of memory for the solve workspace");
            return RB_FAIL;
        }
        rc = rb_chol_solve(h, n, z, z + n, msg, msglen);
        free(z);
        if (rc != RB_OK) return rc;
    }
    return RB_OK;
}

/* x = A^{-1} b with the current factor. Allocation-free: rb_chol_factorize made the workspaces. */
/* The cost of a numeric factorization in solves, from the analysis: its flops over the 4 lnz
 * flops of a forward and a backward sweep (0 before the first factorization). */
double rb_chol_cost_ratio(const void *vh)
{
    const rb_chol *h = vh;
    if (h == NULL || h->L == NULL || h->c.lnz <= 0.0) return 0.0;
    return h->c.fl / (4.0 * h->c.lnz);
}

/* The flops of a solve (a forward and a backward sweep: 4 lnz), 0 before the first factorization. */
double rb_chol_solve_flops(const void *vh)
{
    const rb_chol *h = vh;
    if (h == NULL || h->L == NULL || h->c.lnz <= 0.0) return 0.0;
    return 4.0 * h->c.lnz;
}

int rb_chol_solve(void *vh, int n, const double *b, double *x, char *msg, int msglen)
{
    rb_chol *h = vh;
    int ok;

    if (h == NULL || !h->factored) {
        set_msg(msg, msglen, "CHOLMOD solve: matrix not factorized");
        return RB_BADARG;
    }
    if (n != h->n) {
        set_msg(msg, msglen, "CHOLMOD solve: right-hand side size differs from the matrix order");
        return RB_BADARG;
    }
    last_msg[0] = '\0';
    h->B.nrow = (size_t)n;
    h->B.ncol = 1;
    h->B.nzmax = (size_t)n;
    h->B.d = (size_t)n;
    h->B.x = (void *)b;            /* read only: cholmod_solve2 never writes B */
    h->B.z = NULL;
    h->B.xtype = CHOLMOD_REAL;
    h->B.dtype = CHOLMOD_DOUBLE;
    if (h->Y != NULL && !h->L->is_super && h->Y->nzmax >= 4 * (size_t)n) {
        /* The simplicial solve asks for a 4-by-n Y (cholmod_ensure_dense), then transposes the
         * right-hand side into its first row and leaves Y->nrow = Y->d = 1: the next call would
         * see other dimensions and reallocate Y (two mallocs per solve). Give Y back the shape
         * it is asked for; the memory is the same (nzmax checked). */
        h->Y->nrow = 4;
        h->Y->ncol = (size_t)n;
        h->Y->d = 4;
    }
    ok = cholmod_solve2(CHOLMOD_A, h->L, &h->B, NULL, &h->X, NULL, &h->Y, &h->E, &h->c);
    h->B.x = NULL;
    if (!ok || h->X == NULL || h->c.status < CHOLMOD_OK) return fail(h, msg, msglen, "solve2");
    memcpy(x, h->X->x, (size_t)n * sizeof(double));
    return RB_OK;
}
