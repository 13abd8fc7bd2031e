// The build without MPI: one rank, every collective is local.
#include "volstream/mpi/comm.h"

namespace vs::mpi {

bool available() { return false; }
Session::Session(int&, char**&) {}
Session::~Session() = default;
bool active() { return false; }
int rank() { return 0; }
int size() { return 1; }

void agree(const std::optional<ErrorReport>& mine) {
  if (mine) throw AgreedError(*mine);
}

Image composite(const Image& partial, const std::vector<int>&, CompositeScheme, CompositeStats* stats) {
  if (stats) *stats = {};
  return partial;
}

std::vector<double> gather(const std::vector<double>& mine) { return mine; }

}  // namespace vs::mpi
