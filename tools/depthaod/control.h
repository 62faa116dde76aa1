/* SPDX-License-Identifier: MIT */
/*
 * The control socket: a Unix-domain stream socket taking one JSON object per
 * line and answering one, in order:
 *   {"cmd":"stats"}                           -> {"ok":true,"stats":{...}}
 *   {"cmd":"get"} / {"cmd":"get","key":K}     -> {"ok":true,"params":{...}}
 *   {"cmd":"set","key":K,"value":V}           -> {"ok":true,"key":K,"value":V}
 *   {"cmd":"pause"} / {"cmd":"resume"}        -> {"ok":true,"paused":B}
 *   {"cmd":"snapshot","path":P}               -> {"ok":true,"path":P}
 * Errors: {"ok":false,"error":"..."}; the connection stays usable.
 *
 * Who may connect: the daemon's own user, root, and members of the socket's
 * group (the socket is then mode 0660 and belongs to that group; without one,
 * 0600).  Others are refused and logged.
 *
 * Nothing a client does holds the daemon up: one thread serves every client
 * with non-blocking I/O and bounded buffers.  A client that takes none of its
 * replies for 5 s, or says nothing for the idle timeout, is disconnected; when
 * every slot is taken the longest-idle connection makes room for a new one; a
 * snapshot waits for its frame without blocking anyone else.
 */
#ifndef DAOD_CONTROL_H
#define DAOD_CONTROL_H

#include <stddef.h>

#include "daemon.h"

struct control;

struct control_options {
	const char *path;
	const char *group;       /* NULL or "": "depthao" if that group exists, else none */
	unsigned idle_timeout_s;
};

int control_start(struct control **out, const struct control_options *o, struct daemon *d,
		  char *msg, size_t len);
/* Returns at once: the control thread never blocks on a client. */
void control_stop(struct control *c);

#endif
