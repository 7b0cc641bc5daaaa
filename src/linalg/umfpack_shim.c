/* umfpack_shim.c -- a thin wrapper around UMFPACK (int interface, real) for one square sparse
 * matrix in full compressed-column storage, e.g. the indefinite contact system [S C'; C D].
 *
 * Fortran sees an opaque handle (type(c_ptr)) to rb_umf, which owns: copies of the 0-based
 * pattern (Ap, Ai) and of the values (Ax, kept for the iterative refinement of the solve),
 * the Symbolic and Numeric objects, Control/Info, and the workspaces Wi[n], W[5n] of
 * umfpack_di_wsolve, so that a solve allocates nothing.
 *
 * rb_umf_analyze: pattern only (Ax = NULL), once per pattern; rb_umf_factorize: numeric LU of
 * new values on that pattern (frees the previous Numeric); rb_umf_solve: A x = b.
 *
 * Return codes: RB_UMF_OK, RB_UMF_SINGULAR (numeric found a zero pivot: the factor is dropped
 * and solves are refused until a successful factorize), RB_UMF_FAIL (UMFPACK error),
 * RB_UMF_BADARG (caller error: pattern, sizes, order of calls). Messages are written,
 * NUL-terminated, into the caller's buffer msg[msglen], with UMFPACK's status number. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "umfpack.h"

enum { RB_UMF_OK = 0, RB_UMF_SINGULAR = 1, RB_UMF_FAIL = 2, RB_UMF_BADARG = 3 };

typedef struct {
    int n, nnz;
    int *Ap, *Ai;         /* 0-based pattern, owned */
    double *Ax;           /* values of the current factorization, owned */
    void *symbolic;       /* NULL until analyze succeeded */
    void *numeric;        /* NULL unless factored */
    int factored;         /* numeric holds a nonsingular LU of Ax */
    double control[UMFPACK_CONTROL];
    double info[UMFPACK_INFO];
    int *Wi;              /* wsolve workspace: n */
    double *W;            /* wsolve workspace: 5 n (iterative refinement on) */
} rb_umf;

static void set_msg(char *msg, int msglen, const char *text)
{
    if (msg == NULL || msglen <= 0) return;
    snprintf(msg, (size_t)msglen, "%s", text);
}

/* The meaning of an UMFPACK status (umfpack.h). */
static const char *status_text(int s)
{
    switch (s) {
    case UMFPACK_OK: return "ok";
    case UMFPACK_WARNING_singular_matrix: return "singular matrix";
    case UMFPACK_WARNING_determinant_underflow: return "determinant underflow";
    case UMFPACK_WARNING_determinant_overflow: return "determinant overflow";
    case UMFPACK_ERROR_out_of_memory: return "out of memory";
    case UMFPACK_ERROR_invalid_Numeric_object: return "invalid Numeric object";
    case UMFPACK_ERROR_invalid_Symbolic_object: return "invalid Symbolic object";
    case UMFPACK_ERROR_argument_missing: return "argument missing";
    case UMFPACK_ERROR_n_nonpositive: return "n is not positive";
    case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
    case UMFPACK_ERROR_different_pattern: return "pattern differs from the analyzed one";
    case UMFPACK_ERROR_invalid_system: return "invalid system";
    case UMFPACK_ERROR_invalid_permutation: return "invalid permutation";
    case UMFPACK_ERROR_internal_error: return "internal error";
    case UMFPACK_ERROR_file_IO: return "file I/O error";
    case UMFPACK_ERROR_ordering_failed: return "ordering failed";
    default: return "unknown status";
    }
}

static int fail(char *msg, int msglen, const char *what, int status)
{
    char buf[200];
    snprintf(buf, sizeof buf, "UMFPACK %s failed: %s (UMFPACK status %d)", what, status_text(status), status);
    set_msg(msg, msglen, buf);
    return RB_UMF_FAIL;
}

static void drop_numeric(rb_umf *h)
{
    if (h->numeric != NULL) umfpack_di_free_numeric(&h->numeric);
    h->numeric = NULL;
    h->factored = 0;
}

/* Everything that depends on the pattern: Symbolic, Numeric, copies, workspaces. */
static void drop_pattern(rb_umf *h)
{
    drop_numeric(h);
    if (h->symbolic != NULL) umfpack_di_free_symbolic(&h->symbolic);
    h->symbolic = NULL;
    free(h->Ap);
    free(h->Ai);
    free(h->Ax);
    free(h->Wi);
    free(h->W);
    h->Ap = h->Ai = h->Wi = NULL;
    h->Ax = h->W = NULL;
    h->n = h->nnz = 0;
}

void *rb_umf_new(void)
{
    rb_umf *h = calloc(1, sizeof *h);
    if (h == NULL) return NULL;
    umfpack_di_defaults(h->control);
    h->control[UMFPACK_PRL] = 0;   /* no printing from the library: we report via stat */
    /* Up to 10 steps of iterative refinement (UMFPACK stops as soon as the backward error is at
     * round-off; default 2): the contact system [S C'; C 0] of a stiffness-dominated S (a STATIC
     * preload with 258 imposed DOFs) left the multipliers at 1e-7 of the force scale after 2. */
    h->control[UMFPACK_IRSTEP] = 10;
    return h;
}

void rb_umf_free(void *vh)
{
    rb_umf *h = vh;
    if (h == NULL) return;
    drop_pattern(h);
    free(h);
}

int rb_umf_is_factored(const void *vh)
{
    const rb_umf *h = vh;
    return h != NULL && h->factored;
}

void rb_umf_version(int *v)
{
    v[0] = UMFPACK_MAIN_VERSION;
    v[1] = UMFPACK_SUB_VERSION;
    v[2] = UMFPACK_SUBSUB_VERSION;
}

/* Check and copy the 0-based pattern (colptr0[n+1], rowind0[nnz]), symbolic analysis with
 * Ax = NULL so that the ordering depends on the pattern only. Replaces any previous pattern. */
int rb_umf_analyze(void *vh, int n, int nnz, const int *colptr0, const int *rowind0, char *msg, int msglen)
{
    rb_umf *h = vh;
    char buf[200];
    int j, k, status;
    size_t nz1;

    if (h == NULL) {
        set_msg(msg, msglen, "UMFPACK analyze: null handle");
        return RB_UMF_BADARG;
    }
    drop_pattern(h);
    if (n < 1 || nnz < 0 || colptr0[0] != 0 || colptr0[n] != nnz) {
        snprintf(buf, sizeof buf, "UMFPACK analyze: inconsistent pattern (n = %d, nnz = %d, colptr(1) = %d, "
                 "colptr(n+1) = %d; 1-based)", n, nnz, n >= 1 ? colptr0[0] + 1 : 0, n >= 1 ? colptr0[n] + 1 : 0);
        set_msg(msg, msglen, buf);
        return RB_UMF_BADARG;
    }
    for (j = 0; j < n; j++) {
        if (colptr0[j + 1] < colptr0[j]) {
            snprintf(buf, sizeof buf, "UMFPACK analyze: colptr not monotone at column %d (1-based)", j + 1);
            set_msg(msg, msglen, buf);
            return RB_UMF_BADARG;
        }
    }
    for (j = 0; j < n; j++) {
        for (k = colptr0[j]; k < colptr0[j + 1]; k++) {
            if (rowind0[k] < 0 || rowind0[k] >= n || (k > colptr0[j] && rowind0[k] <= rowind0[k - 1])) {
                snprintf(buf, sizeof buf, "UMFPACK analyze: row %d in column %d is out of range, unsorted or "
                         "repeated (1-based)", rowind0[k] + 1, j + 1);
                set_msg(msg, msglen, buf);
                return RB_UMF_BADARG;
            }
        }
    }

    nz1 = nnz > 0 ? (size_t)nnz : 1;    /* malloc(0) may return NULL */
    h->Ap = malloc((size_t)(n + 1) * sizeof(int));
    h->Ai = malloc(nz1 * sizeof(int));
    h->Ax = malloc(nz1 * sizeof(double));
    h->Wi = malloc((size_t)n * sizeof(int));
    h->W = malloc(5 * (size_t)n * sizeof(double));
    if (h->Ap == NULL || h->Ai == NULL || h->Ax == NULL || h->Wi == NULL || h->W == NULL) {
        drop_pattern(h);
        return fail(msg, msglen, "analyze", UMFPACK_ERROR_out_of_memory);
    }
    memcpy(h->Ap, colptr0, (size_t)(n + 1) * sizeof(int));
    if (nnz > 0) memcpy(h->Ai, rowind0, (size_t)nnz * sizeof(int));
    h->n = n;
    h->nnz = nnz;

    status = umfpack_di_symbolic(n, n, h->Ap, h->Ai, NULL, &h->symbolic, h->control, h->info);
    if (status != UMFPACK_OK || h->symbolic == NULL) {
        drop_pattern(h);
        return fail(msg, msglen, "symbolic", status);
    }
    return RB_UMF_OK;
}

/* Numeric LU of values[nnz] (in the analyzed pattern's order). A singular matrix (a zero
 * pivot) returns RB_UMF_SINGULAR and leaves the handle unfactored. */
int rb_umf_factorize(void *vh, int nnz, const double *values, char *msg, int msglen)
{
    rb_umf *h = vh;
    char buf[200];
    int status;

    if (h == NULL || h->symbolic == NULL) {
        set_msg(msg, msglen, "UMFPACK factorize: pattern not analyzed");
        return RB_UMF_BADARG;
    }
    drop_numeric(h);
    if (nnz != h->nnz) {
        snprintf(buf, sizeof buf, "UMFPACK factorize: %d values for a pattern with %d entries", nnz, h->nnz);
        set_msg(msg, msglen, buf);
        return RB_UMF_BADARG;
    }
    if (nnz > 0) memcpy(h->Ax, values, (size_t)nnz * sizeof(double));
    status = umfpack_di_numeric(h->Ap, h->Ai, h->Ax, h->symbolic, &h->numeric, h->control, h->info);
    if (status == UMFPACK_WARNING_singular_matrix) {
        drop_numeric(h);
        snprintf(buf, sizeof buf, "UMFPACK numeric: %s (UMFPACK status %d): a zero pivot in the LU "
                 "factorization", status_text(status), status);
        set_msg(msg, msglen, buf);
        return RB_UMF_SINGULAR;
    }
    /* The determinant under/overflow warnings leave a valid factor. */
    if (status < UMFPACK_OK || h->numeric == NULL) {
        drop_numeric(h);
        return fail(msg, msglen, "numeric", status);
    }
    h->factored = 1;
    return RB_UMF_OK;
}

/* x = A^{-1} b (UMFPACK_A, with UMFPACK's default iterative refinement). Allocation-free. */
int rb_umf_solve(void *vh, int n, const double *b, double *x, char *msg, int msglen)
{
    rb_umf *h = vh;
    int status;

    if (h == NULL || !h->factored) {
        set_msg(msg, msglen, "UMFPACK solve: matrix not factorized");
        return RB_UMF_BADARG;
    }
    if (n != h->n) {
        set_msg(msg, msglen, "UMFPACK solve: right-hand side size differs from the matrix order");
        return RB_UMF_BADARG;
    }
    status = umfpack_di_wsolve(UMFPACK_A, h->Ap, h->Ai, h->Ax, x, b, h->numeric, h->control, h->info,
                               h->Wi, h->W);
    if (status != UMFPACK_OK) return fail(msg, msglen, "wsolve", status);
    return RB_UMF_OK;
}
