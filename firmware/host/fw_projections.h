/* fw_projections.h: the `projections` scenario of `pp5 reproduce` (gaze paper §6-§7 predictions vs the emulator). */
#ifndef PP5_FW_PROJECTIONS_H
#define PP5_FW_PROJECTIONS_H

/* Prints the table; returns a process exit code. */
int fw_reproduce_projections(int threads);

#endif
