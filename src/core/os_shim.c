/* Signal flag for rebond: SIGINT and SIGTERM only set a flag; the time loop polls it at the end
 * of every step, writes a checkpoint and the summary, and stops (issue 6). Bound in
 * src/os_utils.f90. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>

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
    return 0;
}

/* The signal received since start (0: none). */
int rebond_signal_received(void) { return (int)rebond_signal; }

/* Terminate with a status and no message (Fortran's stop prints "STOP n"); the Fortran
 * runtime closes its units from its own exit handler. */
void rebond_exit(int status) { exit(status); }
