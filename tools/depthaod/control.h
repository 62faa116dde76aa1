/* SPDX-License-Identifier: MIT */
/*
 * The control socket: a Unix-domain stream socket (mode 0600, peers of
 * other users refused) taking one JSON object per line and answering one:
 *   {"cmd":"stats"}                           -> {"ok":true,"stats":{...}}
 *   {"cmd":"get"} / {"cmd":"get","key":K}     -> {"ok":true,"params":{...}}
 *   {"cmd":"set","key":K,"value":V}           -> {"ok":true,"key":K,"value":V}
 *   {"cmd":"pause"} / {"cmd":"resume"}        -> {"ok":true,"paused":B}
 *   {"cmd":"snapshot","path":P}               -> {"ok":true,"path":P}
 * Errors: {"ok":false,"error":"..."}; the connection stays usable.
 */
#ifndef DAOD_CONTROL_H
#define DAOD_CONTROL_H

#include <stddef.h>

#include "daemon.h"

struct control;

int control_start(struct control **out, const char *path, struct daemon *d, char *msg,
		  size_t len);
void control_stop(struct control *c);

#endif
