// The message passing a data-parallel run needs (MPI when the build has it and the process was
// started by mpirun or mpiexec; otherwise one rank, and every call is local). Collective calls
// must be made by every rank in the same order.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/core/image.h"

namespace vs::mpi {

// True when the build has MPI.
bool available();
// True when this process was started by mpirun/mpiexec (Open MPI, MPICH/Hydra or PMIx).
bool launched_by_mpirun();

// MPI_Init on construction (when launched by mpirun), MPI_Finalize on destruction.
class Session {
 public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

bool active();  // a Session initialised MPI
int rank();     // 0 without MPI
int size();     // 1 without MPI

// Collective: every rank says whether it failed. If any did, every rank throws AgreedError with
// the report of the lowest failing rank (rank 0 prints it). No rank is left waiting.
void agree(const std::optional<ErrorReport>& mine);

// Runs `work`, then agrees on its outcome (every rank, whatever `work` throws).
template <typename Work>
void agreed(Work&& work) {
  std::optional<ErrorReport> failure;
  try {
    work();
  } catch (...) {
    failure = describe_error(std::current_exception());
  }
  agree(failure);
}

enum class CompositeScheme { automatic, direct_send, binary_swap };

struct CompositeStats {
  CompositeScheme scheme = CompositeScheme::direct_send;
  double seconds = 0;       // exchange and blending, then the gather
  uint64_t bytes_sent = 0;  // by this rank, exchange and gather
  uint64_t bytes_received = 0;
};

// Collective: blends every rank's premultiplied partial image (all the same size) with "over" in
// `order` (ranks front to back) and gathers the result on rank 0 (others get an empty image).
// automatic: binary swap for a power-of-two rank count, direct send otherwise.
Image composite(const Image& partial, const std::vector<int>& order, CompositeScheme scheme,
                CompositeStats* stats = nullptr);

// Collective: every rank's values, on rank 0 (empty elsewhere), rank after rank.
std::vector<double> gather(const std::vector<double>& mine);

}  // namespace vs::mpi
