/* SPDX-License-Identifier: MIT */
/*
 * Snapshots (`ctl snapshot`): the processing thread copies a shaded frame, a
 * thread of their own writes it, so a slow or stuck file holds up only that thread.
 */

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "daemon_internal.h"

/* The snapshot's result (a frame written, or not): told to whoever waits for it. */
static void snapshot_done(struct daemon *d, int r, const char *msg)
{
	if (d->snapshot_abandoned) {
		d->snapshot_state = SNAP_NONE;
		d->snapshot_abandoned = 0;
		return;
	}
	d->snapshot_state = r < 0 ? r : SNAP_DONE;
	snprintf(d->snapshot_msg, sizeof d->snapshot_msg, "%s", r < 0 ? msg : "");
	if (d->snapshot_notify_fd >= 0) {
		ssize_t w = write(d->snapshot_notify_fd, "s", 1); /* non-blocking pipe */
		(void)w;
	}
}

/*
 * A requested snapshot: the processing thread copies the frame and goes on;
 * the snapshot thread writes it.  Written here, a FIFO whose reader did not
 * read (or a hung network file system) stopped every sink.
 */
void take_snapshot(struct daemon *d, const struct dao_frame *rgb)
{
	pthread_mutex_lock(&d->lock);
	if (d->snapshot_state == SNAP_REQUESTED) {
		if (fq_frame_copy(&d->snapshot_frame, rgb) < 0) {
			snapshot_done(d, -ENOMEM, "out of memory for the snapshot");
		} else {
			d->snapshot_state = SNAP_WRITING;
			pthread_cond_signal(&d->snapshot_cond);
		}
	}
	pthread_mutex_unlock(&d->lock);
}

/*
 * 0 if a snapshot may be written at `path`: a new name, a FIFO or device
 * (dao_png_write decides), an empty file or a PNG.  Any other regular file is
 * refused: `ctl snapshot` with the name of a recording (a typo, or a member of
 * the socket group, who writes as depthaod's user) replaced the running
 * recording with a picture while the recorder went on into the unlinked file.
 */
static int snapshot_may_replace(const char *path, char *msg, size_t len)
{
	static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
	struct stat st;
	if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0)
		return 0;
	unsigned char b[sizeof png_sig];
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
	ssize_t n = fd >= 0 ? read(fd, b, sizeof b) : -1;
	if (fd >= 0)
		close(fd);
	if (n == (ssize_t)sizeof b && !memcmp(b, png_sig, sizeof b))
		return 0;
	snprintf(msg, len, "%s exists and is not a PNG; a snapshot replaces only PNG files "
		 "(remove it or pick another name)", path);
	return -EEXIST;
}

void *snapshot_main(void *arg)
{
	struct daemon *d = arg;
	char path[sizeof d->snapshot_path];
	pthread_mutex_lock(&d->lock);
	for (;;) {
		while (d->snapshot_state != SNAP_WRITING && !d->snapshot_quit)
			pthread_cond_wait(&d->snapshot_cond, &d->lock);
		if (d->snapshot_state != SNAP_WRITING)
			break;
		memcpy(path, d->snapshot_path, sizeof path);
		pthread_mutex_unlock(&d->lock);
		/* the frame is this thread's while the state is SNAP_WRITING */
		struct dao_error err = {0};
		int r = snapshot_may_replace(path, err.message, sizeof err.message);
		if (r == 0)
			r = dao_png_write(path, &d->snapshot_frame, &err);
		pthread_mutex_lock(&d->lock);
		snapshot_done(d, r, err.message);
	}
	pthread_mutex_unlock(&d->lock);
	return NULL;
}

/* Ends the snapshot thread by the deadline; 0 if it is still writing then (a stuck file). */
int stop_snapshot_writer(struct daemon *d, uint64_t deadline)
{
	pthread_mutex_lock(&d->lock);
	d->snapshot_quit = 1;
	pthread_cond_broadcast(&d->snapshot_cond);
	pthread_mutex_unlock(&d->lock);
	if (join_by(d->snapshot_writer, &d->snapshot_writer_running, deadline, NULL))
		return 1;
	log_warn("a snapshot was still being written at the stop deadline (a FIFO nobody "
		 "reads?); it is abandoned");
	return 0;
}

int daemon_snapshot_request(struct daemon *d, const char *path, int notify_fd, char *msg,
			    size_t len)
{
	if (atomic_load(&d->paused)) {
		snprintf(msg, len, "the pipeline is paused: resume it, then take the snapshot");
		return -EAGAIN;
	}
	if (strlen(path) >= sizeof d->snapshot_path) {
		snprintf(msg, len, "the path is longer than %zu bytes", sizeof d->snapshot_path - 1);
		return -ENAMETOOLONG;
	}
	pthread_mutex_lock(&d->lock);
	if (d->params.algorithm == DAO_ALGORITHM_NONE) {
		/* no frame would ever bring a shaded image: say so now, not at the timeout */
		pthread_mutex_unlock(&d->lock);
		snprintf(msg, len, "algorithm is none (the depth only): there is no shaded image; "
			 "set algorithm to gtao (or another) first");
		return -ENODATA;
	}
	if (d->snapshot_state == SNAP_REQUESTED || d->snapshot_state == SNAP_WRITING) {
		pthread_mutex_unlock(&d->lock);
		snprintf(msg, len, "another snapshot is in progress");
		return -EBUSY;
	}
	snprintf(d->snapshot_path, sizeof d->snapshot_path, "%s", path);
	d->snapshot_state = SNAP_REQUESTED;
	d->snapshot_abandoned = 0;
	d->snapshot_notify_fd = notify_fd;
	pthread_mutex_unlock(&d->lock);
	return 0;
}

int daemon_snapshot_result(struct daemon *d, char *msg, size_t len)
{
	pthread_mutex_lock(&d->lock);
	int r = d->snapshot_state;
	if (r == SNAP_REQUESTED || r == SNAP_WRITING) {
		pthread_mutex_unlock(&d->lock);
		return 1;
	}
	if (r < 0)
		snprintf(msg, len, "%s", d->snapshot_msg);
	d->snapshot_state = SNAP_NONE;
	pthread_mutex_unlock(&d->lock);
	return r < 0 ? r : 0;
}

int daemon_snapshot_cancel(struct daemon *d)
{
	pthread_mutex_lock(&d->lock);
	int writing = d->snapshot_state == SNAP_WRITING;
	if (writing)
		d->snapshot_abandoned = 1;
	else
		d->snapshot_state = SNAP_NONE;
	d->snapshot_notify_fd = -1;
	pthread_mutex_unlock(&d->lock);
	return writing;
}
