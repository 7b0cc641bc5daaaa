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
#include <time.h>
#include <dlfcn.h>
#include "cholmod.h"

int rb_chol_solve(void *vh, int n, const double *b, double *x, char *msg, int msglen);

/* BLAS threads. A solve is a sequence of small, memory-bound triangular sweeps (one BLAS call
 * per supernode): threads do not speed it up, and OpenBLAS's helpers spin (sched_yield) after
 * each parallel call, so with its default of one thread per CPU a time loop of solves burned
 * twice its CPU time (measured on a 1e4-equation plate: 3.7 s CPU for 1.9 s of wall time,
 * 2.0 s single-threaded; docs/performance.md). Solves therefore run on one thread and numeric
 * factorizations, whose dense supernodes do gain, on the number OpenBLAS started with (its
 * environment settings respected). Found at run time (dlsym), so another BLAS links as well
 * and is left alone. */
typedef void (*set_threads_fn)(int);
typedef int (*get_threads_fn)(void);
static set_threads_fn blas_set_threads = NULL;
static int blas_threads_all = 1, blas_threads_now = 0, blas_probed = 0;

static void blas_threads(int factorizing)
{
    int want;
    if (!blas_probed) {
        get_threads_fn get = (get_threads_fn)dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
        blas_set_threads = (set_threads_fn)dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
        blas_probed = 1;
        if (get != NULL && blas_set_threads != NULL) blas_threads_all = get();
        blas_threads_now = blas_threads_all;
    }
    if (blas_set_threads == NULL || blas_threads_all <= 1) return;
    want = factorizing ? blas_threads_all : 1;
    if (want != blas_threads_now) {
        blas_set_threads(want);
        blas_threads_now = want;
    }
}

/* The threads a solve and a factorization use (tests, docs/performance.md). */
void rb_blas_threads(int *solve, int *factorize)
{
    blas_threads(0);
    *solve = blas_set_threads != NULL && blas_threads_all > 1 ? 1 : blas_threads_all;
    *factorize = blas_threads_all;
}

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
    int ordering;         /* 1 AMD, 2 METIS on the DOF graph, 3 nested dissection of supervariables */
    double analyze_cpu;   /* CPU seconds of the symbolic analysis */
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

/* From this order on, the analysis is one ordering, CHOLMOD's nested dissection (METIS's
 * separators, CAMD inside) of the graph of supervariables: on a 1e6-equation plate 2.8-3.0 s CPU
 * against 4.6-5.5 s for AMD and METIS on the DOF graph, with 3.4 % less fill (docs/performance.md,
 * finding 5). Below it, the best of AMD and METIS on the DOF graph (milliseconds). */
enum { RB_COMPRESSED_ABOVE = 50000 };

/* A well-mixed 64-bit image of i (splitmix64's finalizer): sums of these identify a pattern. */
static unsigned long long mix(unsigned long long z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* Supervariables: runs of consecutive columns whose full patterns (both triangles) have the same
 * size and the same hash (a node's DOFs). sv[j]: column j's; start[0..*nsv]: their bounds. A
 * hash collision would only merge columns for the ordering: any permutation is a valid one. */
static int supervariables(const cholmod_sparse *A, int *sv, int *start, int *nsv)
{
    const int *Ap = A->p, *Ai = A->i;
    int n = (int)A->ncol, i, j, k, s = -1;
    unsigned long long *hash = calloc((size_t)n, sizeof *hash);
    int *count = calloc((size_t)n, sizeof *count);
    if (hash == NULL || count == NULL) {
        free(hash);
        free(count);
        return 0;
    }
    for (j = 0; j < n; j++)
        for (k = Ap[j]; k < Ap[j + 1]; k++) {
            i = Ai[k];
            hash[j] += mix((unsigned long long)i);
            count[j]++;
            if (i != j) {
                hash[i] += mix((unsigned long long)j);
                count[i]++;
            }
        }
    for (j = 0; j < n; j++) {
        if (j == 0 || count[j] != count[j - 1] || hash[j] != hash[j - 1]) start[++s] = j;
        sv[j] = s;
    }
    *nsv = s + 1;
    start[s + 1] = n;
    free(hash);
    free(count);
    return 1;
}

/* The nested dissection of the supervariable graph, expanded to the columns (each
 * supervariable's columns kept together, in order): Perm[0..n-1]. Returns 0 on failure. */
static int compressed_nesdis(rb_chol *h, int *Perm)
{
    const int *Ap = h->A->p, *Ai = h->A->i;
    cholmod_sparse *G = NULL;
    int *sv, *start, *mark = NULL, *Pg = NULL, *cparent = NULL, *cmember = NULL;
    int n = h->n, nsv = 0, ok = 0, s, j, k, m;
    sv = malloc((size_t)n * sizeof *sv);
    start = malloc(((size_t)n + 1) * sizeof *start);
    if (sv == NULL || start == NULL || !supervariables(h->A, sv, start, &nsv)) goto done;
    G = cholmod_allocate_sparse((size_t)nsv, (size_t)nsv, (size_t)h->nnz, 0, 1, 1, CHOLMOD_PATTERN, &h->c);
    mark = malloc((size_t)nsv * sizeof *mark);
    Pg = malloc((size_t)nsv * sizeof *Pg);
    cparent = malloc((size_t)nsv * sizeof *cparent);
    cmember = malloc((size_t)nsv * sizeof *cmember);
    if (G == NULL || mark == NULL || Pg == NULL || cparent == NULL || cmember == NULL) goto done;
    {
        /* Upper triangle of the quotient graph: an entry (i, j), i <= j, of A gives
         * (sv[i], sv[j]), and sv[i] <= sv[j]; marks drop the repeats. */
        int *Gp = G->p, *Gi = G->i;
        for (s = 0; s < nsv; s++) mark[s] = -1;
        m = 0;
        for (s = 0; s < nsv; s++) {
            Gp[s] = m;
            for (j = start[s]; j < start[s + 1]; j++)
                for (k = Ap[j]; k < Ap[j + 1]; k++)
                    if (mark[sv[Ai[k]]] != s) {
                        mark[sv[Ai[k]]] = s;
                        Gi[m++] = sv[Ai[k]];
                    }
        }
        Gp[nsv] = m;
    }
    if (cholmod_nested_dissection(G, NULL, 0, Pg, cparent, cmember, &h->c) < 0) goto done;
    m = 0;
    for (k = 0; k < nsv; k++)
        for (j = start[Pg[k]]; j < start[Pg[k] + 1]; j++) Perm[m++] = j;
    ok = (m == n);
done:
    free(cmember);
    free(cparent);
    free(Pg);
    free(mark);
    free(start);
    free(sv);
    cholmod_free_sparse(&G, &h->c);
    return ok;
}

/* The symbolic analysis: the supervariables' nested dissection above RB_COMPRESSED_ABOVE, else the best
 * of the methods set in rb_chol_new. */
static cholmod_factor *analyze(rb_chol *h)
{
    cholmod_factor *L = NULL;
    int *Perm;
    if (h->n < RB_COMPRESSED_ABOVE) {
        L = cholmod_analyze(h->A, &h->c);
        h->ordering = L != NULL && h->c.method[h->c.selected].ordering == CHOLMOD_METIS ? 2 : 1;
        return L;
    }
    Perm = malloc((size_t)h->n * sizeof *Perm);
    if (Perm != NULL && compressed_nesdis(h, Perm)) {
        int nm = h->c.nmethods, o0 = h->c.method[0].ordering;
        h->c.nmethods = 1;
        h->c.method[0].ordering = CHOLMOD_GIVEN;
        L = cholmod_analyze_p(h->A, Perm, NULL, 0, &h->c);
        h->c.nmethods = nm;
        h->c.method[0].ordering = o0;
    }
    free(Perm);
    if (L != NULL) {
        h->ordering = 3;
        return L;
    }
    /* Without METIS (or out of memory for it), the usual analysis. */
    last_msg[0] = '\0';
    L = cholmod_analyze(h->A, &h->c);
    h->ordering = L != NULL && h->c.method[h->c.selected].ordering == CHOLMOD_METIS ? 2 : 1;
    return L;
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
        clock_t t0 = clock();
        h->L = analyze(h);
        h->analyze_cpu = (double)(clock() - t0) / CLOCKS_PER_SEC;
        if (h->L == NULL) return fail(h, msg, msglen, "analyze");
    }

    memcpy(h->A->x, values, (size_t)nnz * sizeof(double));
    blas_threads(1);
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

/* What the analysis made, for reports: stats = {nnz(L), entries stored (supernodal blocks),
 * flops of a factorization, ordering (1 AMD, 2 METIS, 3 nested dissection of supervariables), CPU seconds
 * of the analysis, 1 if supernodal}. Returns 0 before the first factorization. */
int rb_chol_stats(const void *vh, double *stats)
{
    const rb_chol *h = vh;
    if (h == NULL || h->L == NULL) return 0;
    stats[0] = h->c.lnz;
    stats[1] = h->L->is_super ? (double)h->L->xsize : h->c.lnz;
    stats[2] = h->c.fl;
    stats[3] = h->ordering;
    stats[4] = h->analyze_cpu;
    stats[5] = h->L->is_super;
    return 1;
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
    blas_threads(0);
    ok = cholmod_solve2(CHOLMOD_A, h->L, &h->B, NULL, &h->X, NULL, &h->Y, &h->E, &h->c);
    h->B.x = NULL;
    if (!ok || h->X == NULL || h->c.status < CHOLMOD_OK) return fail(h, msg, msglen, "solve2");
    memcpy(x, h->X->x, (size_t)n * sizeof(double));
    return RB_OK;
}
