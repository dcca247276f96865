/**
 * vtkRayMapperThreads: how many threads the mappers of this process may use.
 *
 * The mappers run their kernels on TBB, which by default takes every core of the machine.
 * Several MPI ranks on one machine (pvbatch or pvserver under mpirun) would then each start
 * that many threads and oversubscribe the cores. The first representation made in a
 * process caps TBB's parallelism for the whole process:
 * - RAYMAPPERS_THREADS=N in the environment: N threads;
 * - else, under MPI with L ranks on this machine (Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE,
 *   MPICH's MPI_LOCALNRANKS): the cores divided among them, at least one each;
 * - else no cap.
 */
#ifndef vtkRayMapperThreads_h
#define vtkRayMapperThreads_h

/// Applies the cap once per process (later calls do nothing); returns the number of threads
/// the kernels may use (the machine's cores when there is no cap).
int vtkRayMapperLimitThreads();

#endif
