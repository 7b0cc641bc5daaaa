/* Checked text output for rebond's result files (history.csv, probes.csv, events.csv,
 * contacts.csv, fields.xmf, sweep.csv). gfortran's FLUSH and CLOSE do not report a failed
 * write(2) (a full disk goes unseen, issue 12), so these files are written here with
 * write(2), unbuffered (one call per line); every errno goes back to src/core/text_file.f90,
 * which words the message.
 *
 * A handle remembers the end of the last complete line in the file: after a failed write
 * the file is cut back to it, so a result file never ends with half a line. A symbolic
 * link planted at a result file's path is replaced, never written through
 * (docs/reliability.md). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/uio.h>
#include <unistd.h>

typedef struct {
    int fd;
    off_t good; /* bytes known to be complete in the file */
} rebond_file;

/* Open path for writing: mode 0 creates (an existing file or link is replaced), mode 1
 * writes at the end of an existing regular file. NULL with *err = errno on failure. */
void *rebond_file_open(const char *path, int mode, int *err)
{
    struct stat st;
    int fd;
    rebond_file *f;
    *err = 0;
    if (mode == 0 && lstat(path, &st) == 0 && S_ISLNK(st.st_mode) && unlink(path) != 0) {
        *err = errno;
        return NULL;
    }
    if (mode == 0)
        fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644);
    else /* not O_APPEND: pwrite(2) must honour its offset (replace_tail) */
        fd = open(path, O_WRONLY | O_NOFOLLOW);
    if (fd < 0) {
        *err = errno;
        return NULL;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        *err = S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
        close(fd);
        return NULL;
    }
    f = malloc(sizeof *f);
    if (f == NULL) {
        *err = ENOMEM;
        close(fd);
        return NULL;
    }
    f->fd = fd;
    f->good = st.st_size;
    if (mode != 0 && lseek(fd, 0, SEEK_END) < 0) {
        *err = errno;
        close(fd);
        free(f);
        return NULL;
    }
    return f;
}

/* n bytes of buf, then a newline if newline != 0, to fd in writev(2) calls until all is out
 * (short writes continued, EINTR retried). Returns 0 or errno (ENOSPC for a write of 0). */
static int write_all(int fd, const char *buf, size_t n, int newline)
{
    static const char nl = '\n';
    struct iovec iov[2];
    int cnt = newline ? 2 : 1;
    ssize_t w;
    iov[0].iov_base = (void *)buf;
    iov[0].iov_len = n;
    iov[1].iov_base = (void *)&nl;
    iov[1].iov_len = 1;
    if (n == 0 && !newline) return 0;
    while (cnt > 0) {
        w = writev(fd, iov, cnt);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return (w < 0) ? errno : ENOSPC;
        /* A short write: skip what went out and go on with the rest. */
        while (cnt > 0 && (size_t)w >= iov[0].iov_len) {
            w -= (ssize_t)iov[0].iov_len;
            iov[0] = iov[1];
            cnt--;
        }
        if (cnt > 0) {
            iov[0].iov_base = (char *)iov[0].iov_base + w;
            iov[0].iov_len -= (size_t)w;
        }
    }
    return 0;
}

/* Append n bytes of buf, then a newline if newline != 0, in one writev(2) (unbuffered: the
 * bytes are in the file when this returns 0). Returns 0 or errno; on failure the file is cut
 * back to the end of the last complete write. */
int rebond_file_write(void *handle, const char *buf, size_t n, int newline)
{
    rebond_file *f = handle;
    int err = write_all(f->fd, buf, n, newline);
    if (err != 0) {
        (void)ftruncate(f->fd, f->good);
        (void)lseek(f->fd, f->good, SEEK_SET);
        return err;
    }
    f->good += (off_t)(n + (newline ? 1 : 0));
    return 0;
}

/* Write n bytes of buf and a newline to standard output (fd 1), unbuffered, short writes and
 * EINTR taken care of. Returns 0 or errno (ENOSPC on /dev/full, EPIPE on a closed pipe), so that
 * the run's report is checked like its result files. */
int rebond_stdout_line(const char *buf, size_t n)
{
    static int pipe_ignored = 0;
    /* A reader that goes away (rebond scene | head) must not kill the run: EPIPE instead of
     * SIGPIPE, said at the end, results complete. */
    if (!pipe_ignored) {
        signal(SIGPIPE, SIG_IGN);
        pipe_ignored = 1;
    }
    return write_all(1, buf, n, 1);
}

/* Overwrite the last tail_len bytes of the file with buf (n >= tail_len bytes, ending with the
 * same tail) in one pwrite(2), so that the file is complete before and after: fields.xmf
 * gains a step without being rewritten. On failure the old tail (the end of buf) is put back
 * and the file cut to its old length. Returns 0 or errno. */
int rebond_file_replace_tail(void *handle, const char *buf, size_t n, size_t tail_len)
{
    rebond_file *f = handle;
    off_t at = f->good - (off_t)tail_len;
    ssize_t w;
    int err;
    if (at < 0 || tail_len > n) return EINVAL;
    do {
        w = pwrite(f->fd, buf, n, at);
    } while (w < 0 && errno == EINTR);
    if (w == (ssize_t)n) {
        f->good = at + (off_t)n;
        (void)lseek(f->fd, f->good, SEEK_SET);
        return 0;
    }
    err = (w < 0) ? errno : ENOSPC;
    (void)pwrite(f->fd, buf + (n - tail_len), tail_len, at);
    (void)ftruncate(f->fd, f->good);
    return err;
}

/* Close; returns 0 or errno (the handle is freed either way). */
int rebond_file_close(void *handle)
{
    rebond_file *f = handle;
    int err = 0;
    if (close(f->fd) != 0) err = errno;
    free(f);
    return err;
}

/* The system's text for errno err, NUL-terminated in buf (len bytes). */
void rebond_strerror(int err, char *buf, int len)
{
    const char *s = strerror(err);
    if (len <= 0) return;
    strncpy(buf, s, (size_t)len - 1);
    buf[len - 1] = '\0';
}

/* Bytes that can still be added to the file at path (it may not exist yet) whose directory
 * is dir: the space available to this user on dir's file system, and no more than the file
 * size limit (ulimit -f) allows. -1: unknown. */
double rebond_room(const char *path, const char *dir)
{
    struct statvfs sv;
    struct stat st;
    struct rlimit rl;
    double room;
    if (statvfs(dir, &sv) != 0) return -1.0;
    room = (double)sv.f_bavail * (double)sv.f_frsize;
    if (getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
        double used = (stat(path, &st) == 0) ? (double)st.st_size : 0.0;
        double left = (double)rl.rlim_cur - used;
        if (left < room) room = left < 0.0 ? 0.0 : left;
    }
    return room;
}

/* The calling thread's errno, then cleared: read after a library call failed (HDF5 does not
 * pass on why a write failed), cleared after one succeeded. */
int rebond_take_errno(void)
{
    int e = errno;
    errno = 0;
    return e;
}

/* If path is a symbolic link, remove the link (not its target). Returns 0 or errno. */
int rebond_unlink_symlink(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0 || !S_ISLNK(st.st_mode)) return 0;
    return unlink(path) == 0 ? 0 : errno;
}
