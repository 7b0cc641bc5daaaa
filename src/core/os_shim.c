/* Signal flag for rebond: SIGINT and SIGTERM only set a flag; the time loop polls it at the end
 * of every step, writes a checkpoint and the summary, and stops (issue 6). Bound in
 * src/os_utils.f90. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static volatile sig_atomic_t rebond_signal = 0;

static void rebond_on_signal(int sig) { rebond_signal = sig; }

/* Returns 0 on success, -1 if a handler could not be installed. */
int rebond_install_signal_handlers(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = rebond_on_signal;
    sigemptyset(&sa.sa_mask);
    if (sigaction(SIGINT, &sa, NULL) != 0) return -1;
    if (sigaction(SIGTERM, &sa, NULL) != 0) return -1;
    /* A file size limit (ulimit -f) makes write(2) fail with EFBIG, reported like a full
     * disk, instead of killing the process. */
    sa.sa_handler = SIG_IGN;
    if (sigaction(SIGXFSZ, &sa, NULL) != 0) return -1;
    return 0;
}

/* The signal received since start (0: none). */
int rebond_signal_received(void) { return (int)rebond_signal; }

/* Terminate with a status and no message (Fortran's stop prints "STOP n"); the Fortran
 * runtime closes its units from its own exit handler. */
void rebond_exit(int status) { exit(status); }

/* Terminate without running the exit handlers: after an HDF5 failure on a full disk, HDF5's
 * own handler would crash closing the file it could not close (HDF5 1.10, H5F__close_cb).
 * Every result file of rebond is closed or unbuffered by then. */
void rebond_exit_now(int status) { _exit(status); }
