/* SPDX-License-Identifier: MIT */
/*
 * A full disk without root, for tests: LD_PRELOAD this module and the
 * write(), pwrite(), writev() and pwritev() calls of the process on files
 * whose path contains a given text fail with ENOSPC once a budget of bytes
 * is used up; the call that crosses it writes what still fits and returns
 * that short count, as a file system does when it fills up.  fsync() and
 * fdatasync() on those files can be logged.  ftruncate() that makes such a
 * file shorter gives the bytes back, as freeing blocks does.
 *
 * Set up from the environment at the first call:
 *   DAO_ENOSPC_PATH   text the file's path must contain (unset: no file fails)
 *   DAO_ENOSPC_AFTER  bytes that fit, over all matching files (default 0)
 *   DAO_SYNC_LOG      append "<monotonic ms> fdatasync|fsync <path>" per sync here
 * or at run time through dao_enospc_set() (a test finds it with dlsym; it
 * resets the byte count).  dao_sync_fail_set(text, errnum) makes fsync() and
 * fdatasync() on files whose path contains `text` fail with errnum (0: no
 * longer), as a disk that reports a write-back error does.
 */
#undef _FILE_OFFSET_BITS /* define pwrite and pwrite64 as the two symbols they are */
#define _GNU_SOURCE /* RTLD_NEXT, off64_t */
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#define EXPORT __attribute__((visibility("default")))

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static int configured;
static char match[PATH_MAX];
static long long budget, used;
static char sync_log[PATH_MAX];
static char sync_fail_match[PATH_MAX];
static int sync_fail_errno;

static void configure_locked(void)
{
	if (configured)
		return;
	configured = 1;
	const char *p = getenv("DAO_ENOSPC_PATH"), *a = getenv("DAO_ENOSPC_AFTER");
	const char *l = getenv("DAO_SYNC_LOG");
	snprintf(match, sizeof match, "%s", p ? p : "");
	budget = a ? atoll(a) : 0;
	snprintf(sync_log, sizeof sync_log, "%s", l ? l : "");
}

EXPORT void dao_enospc_set(const char *path_contains, long long bytes);
void dao_enospc_set(const char *path_contains, long long bytes)
{
	pthread_mutex_lock(&lock);
	configured = 1;
	snprintf(match, sizeof match, "%s", path_contains ? path_contains : "");
	budget = bytes;
	used = 0;
	pthread_mutex_unlock(&lock);
}

EXPORT void dao_sync_fail_set(const char *path_contains, int errnum);
void dao_sync_fail_set(const char *path_contains, int errnum)
{
	pthread_mutex_lock(&lock);
	snprintf(sync_fail_match, sizeof sync_fail_match, "%s", path_contains ? path_contains : "");
	sync_fail_errno = errnum;
	pthread_mutex_unlock(&lock);
}

/* The path of fd if it contains the configured text, else 0. */
static int fd_path(int fd, char *path, size_t len)
{
	char link[64];
	snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
	ssize_t n = readlink(link, path, len - 1);
	if (n < 0)
		return 0;
	path[n] = '\0';
	return 1;
}

static int matches(int fd)
{
	char path[PATH_MAX];
	return match[0] && fd_path(fd, path, sizeof path) && strstr(path, match) != NULL;
}

/* How many of n bytes may be written to fd: n, fewer, or 0 (then ENOSPC). */
static size_t allowance(int fd, size_t n)
{
	pthread_mutex_lock(&lock);
	configure_locked();
	size_t ok = n;
	if (n && matches(fd)) {
		long long left = budget > used ? budget - used : 0;
		ok = (long long)n < left ? n : (size_t)left;
		used += (long long)ok;
	}
	pthread_mutex_unlock(&lock);
	return ok;
}

static void log_sync(int fd, const char *what)
{
	char path[PATH_MAX];
	pthread_mutex_lock(&lock);
	configure_locked();
	if (sync_log[0] && matches(fd) && fd_path(fd, path, sizeof path)) {
		struct timespec t;
		clock_gettime(CLOCK_MONOTONIC, &t);
		FILE *f = fopen(sync_log, "a");
		if (f) {
			fprintf(f, "%lld %s %s\n", (long long)t.tv_sec * 1000 + t.tv_nsec / 1000000, what,
				path);
			fclose(f);
		}
	}
	pthread_mutex_unlock(&lock);
}

#define REAL(name, ret, ...)                                                                   \
	static ret (*real_##name)(__VA_ARGS__);                                                \
	if (!real_##name)                                                                      \
		real_##name = (ret(*)(__VA_ARGS__))dlsym(RTLD_NEXT, #name)

static size_t iov_total(const struct iovec *iov, int cnt)
{
	size_t n = 0;
	for (int i = 0; i < cnt; i++)
		n += iov[i].iov_len;
	return n;
}

/* The first `n` bytes of iov as a shorter vector (in `out`); returns its count. */
static int iov_cut(const struct iovec *iov, int cnt, size_t n, struct iovec *out)
{
	int k = 0;
	for (int i = 0; i < cnt && n; i++, k++) {
		out[k] = iov[i];
		if (out[k].iov_len > n)
			out[k].iov_len = n;
		n -= out[k].iov_len;
	}
	return k;
}

EXPORT ssize_t write(int fd, const void *buf, size_t n)
{
	REAL(write, ssize_t, int, const void *, size_t);
	size_t ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	return real_write(fd, buf, ok);
}

EXPORT ssize_t pwrite(int fd, const void *buf, size_t n, off_t at)
{
	REAL(pwrite, ssize_t, int, const void *, size_t, off_t);
	size_t ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	return real_pwrite(fd, buf, ok, at);
}

EXPORT ssize_t pwrite64(int fd, const void *buf, size_t n, off64_t at)
{
	REAL(pwrite64, ssize_t, int, const void *, size_t, off64_t);
	size_t ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	return real_pwrite64(fd, buf, ok, at);
}

EXPORT ssize_t writev(int fd, const struct iovec *iov, int cnt)
{
	REAL(writev, ssize_t, int, const struct iovec *, int);
	size_t n = iov_total(iov, cnt), ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	if (ok == n)
		return real_writev(fd, iov, cnt);
	struct iovec cut[IOV_MAX];
	return real_writev(fd, cut, iov_cut(iov, cnt < IOV_MAX ? cnt : IOV_MAX, ok, cut));
}

EXPORT ssize_t pwritev(int fd, const struct iovec *iov, int cnt, off_t at)
{
	REAL(pwritev, ssize_t, int, const struct iovec *, int, off_t);
	size_t n = iov_total(iov, cnt), ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	if (ok == n)
		return real_pwritev(fd, iov, cnt, at);
	struct iovec cut[IOV_MAX];
	return real_pwritev(fd, cut, iov_cut(iov, cnt < IOV_MAX ? cnt : IOV_MAX, ok, cut), at);
}

EXPORT ssize_t pwritev64(int fd, const struct iovec *iov, int cnt, off64_t at)
{
	REAL(pwritev64, ssize_t, int, const struct iovec *, int, off64_t);
	size_t n = iov_total(iov, cnt), ok = allowance(fd, n);
	if (n && !ok) {
		errno = ENOSPC;
		return -1;
	}
	if (ok == n)
		return real_pwritev64(fd, iov, cnt, at);
	struct iovec cut[IOV_MAX];
	return real_pwritev64(fd, cut, iov_cut(iov, cnt < IOV_MAX ? cnt : IOV_MAX, ok, cut), at);
}

/* Cutting a file back frees its space, as on a file system. */
static void give_back(int fd, off_t length)
{
	struct stat st;
	pthread_mutex_lock(&lock);
	configure_locked();
	if (matches(fd) && fstat(fd, &st) == 0 && length < st.st_size) {
		used -= (long long)(st.st_size - length);
		if (used < 0)
			used = 0;
	}
	pthread_mutex_unlock(&lock);
}

EXPORT int ftruncate(int fd, off_t length)
{
	REAL(ftruncate, int, int, off_t);
	give_back(fd, length);
	return real_ftruncate(fd, length);
}

EXPORT int ftruncate64(int fd, off64_t length)
{
	REAL(ftruncate64, int, int, off64_t);
	give_back(fd, (off_t)length);
	return real_ftruncate64(fd, length);
}

/* The errno a sync of fd fails with (dao_sync_fail_set), or 0. */
static int sync_failure(int fd)
{
	char path[PATH_MAX];
	pthread_mutex_lock(&lock);
	int e = sync_fail_errno && sync_fail_match[0] && fd_path(fd, path, sizeof path) &&
			strstr(path, sync_fail_match)
		? sync_fail_errno
		: 0;
	pthread_mutex_unlock(&lock);
	return e;
}

EXPORT int fdatasync(int fd)
{
	REAL(fdatasync, int, int);
	log_sync(fd, "fdatasync");
	int e = sync_failure(fd);
	if (e) {
		errno = e;
		return -1;
	}
	return real_fdatasync(fd);
}

EXPORT int fsync(int fd)
{
	REAL(fsync, int, int);
	log_sync(fd, "fsync");
	int e = sync_failure(fd);
	if (e) {
		errno = e;
		return -1;
	}
	return real_fsync(fd);
}
