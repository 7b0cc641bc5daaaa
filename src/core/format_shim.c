/* format_shim.c -- one real as text, without the Fortran I/O runtime (bound in
 * src/text_format.f90). A formatted internal WRITE allocates several blocks in libgfortran
 * (unit, stream, format copy and parse tree) at every statement; the history rows are written
 * at every step, so they are built from these pieces instead (docs/performance.md).
 *
 * rb_format_es writes x into out[0..31] as Fortran's ES24.16E3 edit descriptor does (17
 * significant digits, 3-digit exponent), without the leading blanks, and returns the length.
 * libgfortran itself formats ES through snprintf("%e") with the same precision, so the digits
 * (and their rounding) are the C library's in both cases; tests/unit/test_text_format.f90
 * compares the two. Nothing is allocated: glibc's printf keeps a double's 17 digits on the stack. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rb_format_es(double x, char *out)
{
    char m[48];
    const char *e;
    int k, ex;
    if (isnan(x)) {
        memcpy(out, "NaN", 3);
        return 3;
    }
    if (isinf(x)) {
        if (x < 0) {
            memcpy(out, "-Infinity", 9);
            return 9;
        }
        memcpy(out, "Infinity", 8);
        return 8;
    }
    snprintf(m, sizeof m, "%.16e", x);   /* [-]d.dddddddddddddddde[+-]dd[d] */
    e = strchr(m, 'e');
    if (e == NULL) return 0;
    k = (int)(e - m);
    memcpy(out, m, (size_t)k);
    ex = atoi(e + 1);
    out[k++] = 'E';
    out[k++] = ex < 0 ? '-' : '+';
    ex = abs(ex);
    out[k++] = (char)('0' + ex / 100);
    out[k++] = (char)('0' + (ex / 10) % 10);
    out[k++] = (char)('0' + ex % 10);
    return k;
}
