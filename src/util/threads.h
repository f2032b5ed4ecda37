/* threads.h — how many threads a run may use: the OpenMP runtime's count, which
 * follows OMP_NUM_THREADS when it is set and the process's CPU affinity mask
 * otherwise; 1 in a build without OpenMP. And the wait of one thread for another's
 * flag (the fused step's hand-overs, the stability check's barriers). */
#ifndef ESF_THREADS_H
#define ESF_THREADS_H

int esf_threads_available(void);

/* Spins until *flag reaches e (flags only grow; acquire order, so what was stored
 * before the flag went up is visible), then yields the core between looks (more
 * threads than cores); returns the seconds waited, 0 when it was already up. */
double esf_threads_wait(_Atomic long *flag, long e);

#endif
