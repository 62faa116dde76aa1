/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_EVAL_SEQUENCE_H
#define DAO_TOOLS_EVAL_SEQUENCE_H

/* depthao eval --sequence PATH ... (eval_sequence.c); the exit status. */
int cmd_eval_sequence(int argc, char **argv);

#endif
