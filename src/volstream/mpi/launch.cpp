#include <cstdlib>

#include "volstream/mpi/comm.h"

namespace vs::mpi {

bool launched_by_mpirun() {
  // Open MPI's mpirun, MPICH's Hydra (PMI) and PMIx launchers (srun) set these in every rank.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_RANK", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace vs::mpi
