// The build with MPI (CMake VOLSTREAM_MPI): compositing by direct send (any rank count) or
// binary swap (powers of two), on premultiplied float RGBA, then a gather on rank 0.
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstddef>

#include "volstream/core/stopwatch.h"
#include "volstream/mpi/comm.h"
#include "volstream/mpi/compositing.h"

namespace vs::mpi {
namespace {

bool g_active = false;

int count_of(uint64_t floats) {
  if (floats > uint64_t(INT_MAX)) throw UsageError("image too large for one MPI message");
  return int(floats);
}

// Each rank's position in the visibility order.
std::vector<int> positions(const std::vector<int>& order) {
  std::vector<int> pos(order.size());
  for (size_t i = 0; i < order.size(); ++i) pos[size_t(order[i])] = int(i);
  return pos;
}

// The pixels rank r holds after binary swap: the round-k partner is r ^ 2^k, and the rank with
// bit k clear keeps the first half.
PixelRange binary_swap_range(uint64_t pixels, int ranks, int r) {
  PixelRange range{0, pixels};
  for (int bit = 1; bit < ranks; bit <<= 1) {
    const uint64_t mid = range.begin + range.size() / 2;
    range = (r & bit) ? PixelRange{mid, range.end} : PixelRange{range.begin, mid};
  }
  return range;
}

// Direct send: rank j blends piece j of every rank's image; returns this rank's piece.
std::vector<float> direct_send(const Image& partial, const std::vector<int>& order, CompositeStats& stats) {
  const int n = size(), me = rank();
  const uint64_t pixels = uint64_t(partial.width) * partial.height;
  const PixelRange mine = piece(pixels, n, me);
  const size_t ranks = size_t(n);
  std::vector<int> send_counts(ranks), send_displs(ranks), recv_counts(ranks), recv_displs(ranks);
  for (int j = 0; j < n; ++j) {
    const PixelRange p = piece(pixels, n, j);
    send_counts[size_t(j)] = count_of(4 * p.size());
    send_displs[size_t(j)] = count_of(4 * p.begin);
    recv_counts[size_t(j)] = count_of(4 * mine.size());
    recv_displs[size_t(j)] = count_of(4 * mine.size() * uint64_t(j));
  }
  std::vector<float> pieces(4 * mine.size() * uint64_t(n));
  MPI_Alltoallv(partial.rgba.data(), send_counts.data(), send_displs.data(), MPI_FLOAT, pieces.data(),
                recv_counts.data(), recv_displs.data(), MPI_FLOAT, MPI_COMM_WORLD);
  stats.bytes_sent += 4 * sizeof(float) * (pixels - mine.size());
  stats.bytes_received += 4 * sizeof(float) * mine.size() * uint64_t(n - 1);
  const uint64_t floats = 4 * mine.size();
  std::vector<float> out(pieces.begin() + ptrdiff_t(floats * size_t(order[0])),
                         pieces.begin() + ptrdiff_t(floats * size_t(order[0] + 1)));
  for (size_t k = 1; k < order.size(); ++k)
    blend_over(out.data(), pieces.data() + floats * size_t(order[k]), mine.size());
  return out;
}

// Binary swap: log2(n) rounds of exchanging half of the pixels still held with a partner.
std::vector<float> binary_swap(const Image& partial, const std::vector<int>& order, CompositeStats& stats) {
  const int n = size(), me = rank();
  const std::vector<int> pos = positions(order);
  std::vector<float> image = partial.rgba;
  PixelRange range{0, uint64_t(partial.width) * partial.height};
  std::vector<float> received;
  for (int bit = 1; bit < n; bit <<= 1) {
    const int partner = me ^ bit;
    const uint64_t mid = range.begin + range.size() / 2;
    const PixelRange keep = (me & bit) ? PixelRange{mid, range.end} : PixelRange{range.begin, mid};
    const PixelRange give = (me & bit) ? PixelRange{range.begin, mid} : PixelRange{mid, range.end};
    received.resize(4 * keep.size());
    MPI_Sendrecv(image.data() + 4 * give.begin, count_of(4 * give.size()), MPI_FLOAT, partner, bit, received.data(),
                 count_of(4 * keep.size()), MPI_FLOAT, partner, bit, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    stats.bytes_sent += 4 * sizeof(float) * give.size();
    stats.bytes_received += 4 * sizeof(float) * keep.size();
    float* kept = image.data() + 4 * keep.begin;
    if (pos[size_t(me)] < pos[size_t(partner)])
      blend_over(kept, received.data(), keep.size());
    else
      blend_under(received.data(), kept, keep.size());
    range = keep;
  }
  return {image.begin() + ptrdiff_t(4 * range.begin), image.begin() + ptrdiff_t(4 * range.end)};
}

// Rank 0 assembles every rank's finished pixels.
Image gather_image(const std::vector<float>& mine, uint32_t width, uint32_t height, bool swapped,
                   CompositeStats& stats) {
  const int n = size();
  const uint64_t pixels = uint64_t(width) * height;
  const size_t ranks = size_t(n);
  std::vector<int> counts(ranks), displs(ranks);
  for (int j = 0; j < n; ++j) {
    const PixelRange p = swapped ? binary_swap_range(pixels, n, j) : piece(pixels, n, j);
    counts[size_t(j)] = count_of(4 * p.size());
    displs[size_t(j)] = count_of(4 * p.begin);
  }
  Image out;
  if (rank() == 0) out = Image(width, height);
  MPI_Gatherv(mine.data(), count_of(mine.size()), MPI_FLOAT, out.rgba.data(), counts.data(), displs.data(), MPI_FLOAT,
              0, MPI_COMM_WORLD);
  if (rank() != 0) stats.bytes_sent += mine.size() * sizeof(float);
  return out;
}

}  // namespace

bool available() { return true; }

Session::Session(int& argc, char**& argv) {
  if (!launched_by_mpirun()) return;
  MPI_Init(&argc, &argv);
  g_active = true;
}

Session::~Session() {
  if (g_active) MPI_Finalize();
  g_active = false;
}

bool active() { return g_active; }

int rank() {
  int r = 0;
  if (g_active) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  int n = 1;
  if (g_active) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

void agree(const std::optional<ErrorReport>& mine) {
  if (!g_active) {
    if (mine) throw AgreedError(*mine);
    return;
  }
  const int n = size();
  const int my_code = mine ? rank() : n;
  int first = n;
  MPI_Allreduce(&my_code, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == n) return;
  // The lowest failing rank tells everyone what went wrong.
  ErrorReport report = mine && rank() == first ? *mine : ErrorReport{};
  int length = int(report.line.size());
  MPI_Bcast(&report.status, 1, MPI_INT, first, MPI_COMM_WORLD);
  MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
  report.line.resize(size_t(length));
  MPI_Bcast(report.line.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
  throw AgreedError(report);
}

Image composite(const Image& partial, const std::vector<int>& order, CompositeScheme scheme, CompositeStats* stats) {
  CompositeStats local;
  Stopwatch watch;
  const int n = size();
  const bool power_of_two = (n & (n - 1)) == 0;
  if (scheme == CompositeScheme::automatic)
    scheme = power_of_two ? CompositeScheme::binary_swap : CompositeScheme::direct_send;
  if (scheme == CompositeScheme::binary_swap && !power_of_two)
    throw UsageError("binary swap needs a power-of-two rank count (use direct send)");
  local.scheme = scheme;
  Image out;
  if (!g_active) {
    out = partial;
  } else {
    const bool swapped = scheme == CompositeScheme::binary_swap;
    const std::vector<float> mine = swapped ? binary_swap(partial, order, local) : direct_send(partial, order, local);
    out = gather_image(mine, partial.width, partial.height, swapped, local);
  }
  local.seconds = watch.seconds();
  if (stats) *stats = local;
  return out;
}

std::vector<double> gather(const std::vector<double>& mine) {
  if (!g_active) return mine;
  std::vector<double> all(rank() == 0 ? mine.size() * size_t(size()) : 0);
  MPI_Gather(mine.data(), count_of(mine.size()), MPI_DOUBLE, all.data(), count_of(mine.size()), MPI_DOUBLE, 0,
             MPI_COMM_WORLD);
  return all;
}

}  // namespace vs::mpi
