#!/bin/sh
# Runs an MPI program on N ranks of this machine: run_mpi.sh N program [args].
# --oversubscribe: more ranks than cores; as root, OpenMPI wants to be told.
n=$1
shift
if [ "$(id -u)" = 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# Under AddressSanitizer, leak checking is off: OpenMPI keeps allocations
# until exit in plugins it unloads first, which LeakSanitizer then cannot
# name or suppress. Memory errors and undefined behaviour are still fatal.
if [ -n "${ASAN_OPTIONS:-}" ]; then
    export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
fi
# OpenMPI's shared-memory transport copies large messages with
# process_vm_readv (CMA) by default; where the kernel or a VM refuses or slows
# it, each exchange stalls for tens of milliseconds: plain copies instead.
export OMPI_MCA_btl_vader_single_copy_mechanism=${OMPI_MCA_btl_vader_single_copy_mechanism:-none}
# A waiting rank yields its core (as OpenMPI does by itself only with more
# ranks than cores): the cores are shared with the other ranks and jobs.
export OMPI_MCA_mpi_yield_when_idle=${OMPI_MCA_mpi_yield_when_idle:-1}
# One thread per rank; no binding (the ranks share the cores with others).
exec mpirun --oversubscribe --bind-to none -x OMP_NUM_THREADS=1 -x OMP_WAIT_POLICY=passive -np "$n" "$@"
