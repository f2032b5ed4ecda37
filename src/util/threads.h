/* threads.h — how many threads a run may use: the OpenMP runtime's count, which
 * follows OMP_NUM_THREADS when it is set and the process's CPU affinity mask
 * otherwise; 1 in a build without OpenMP. */
#ifndef ESF_THREADS_H
#define ESF_THREADS_H

int esf_threads_available(void);

#endif
