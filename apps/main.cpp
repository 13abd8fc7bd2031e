// volstream: the command-line tool. Errors in input become one line on stderr and exit status 2
// (under mpirun: one line from rank 0, every rank exits with it).
#include <malloc.h>

#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "commands.h"
#include "volstream/core/error.h"
#include "volstream/mpi/comm.h"

namespace {
// Under mpirun every rank meets the same error (or agreed on one, mpi/comm.h): rank 0 says it.
int report(const vs::ErrorReport& e) {
  if (vs::mpi::rank() == 0) std::fprintf(stderr, "volstream: %s\n", e.line.c_str());
  return e.status;
}

// glibc serves each block over its mmap threshold (at most 32 MiB) with a fresh mapping and
// unmaps it when freed, and gives the heap's free top back above 128 KiB: a reader that builds
// and drops large arrays step after step then pays the kernel's page faults and zeroing every
// time (most of a polyhedral series' read: bench/RESULTS.md, "Memory kept for reuse"). From the
// heap, kept up to 1 GiB free, the memory is reused. Peak memory is the same or a little more.
void keep_freed_memory_for_reuse() {
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}
}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_for_reuse();
  vs::mpi::Session mpi_session(argc, argv);  // MPI only when started by mpirun
  CLI::App app{"volstream: streaming renderer for huge time-varying AMR volumes"};
  app.require_subcommand(1);
  vs::cli::add_demo_command(app);
  vs::cli::add_convert_command(app);
  vs::cli::add_info_command(app);
  vs::cli::add_probe_command(app);
  vs::cli::add_render_command(app);
  vs::cli::add_play_command(app);
  vs::cli::add_timeline_command(app);
  vs::cli::add_bench_command(app);
#ifdef VOLSTREAM_HAVE_VIEWER
  vs::cli::add_view_command(app);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help: the help text
    // One line like every other bad input (CLI11's own message adds a second line).
    std::string message = e.what();
    for (char& c : message)
      if (c == '\n') c = ' ';
    return report({message + " (--help lists the options)", 2});
  } catch (const vs::AgreedError& e) {
    return report(e.report());
  } catch (...) {
    return report(vs::describe_error(std::current_exception()));
  }
  return 0;
}
