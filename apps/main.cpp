// volstream: the command-line tool. Errors in input become one line on stderr and exit status 2.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "commands.h"
#include "volstream/core/error.h"

int main(int argc, char** argv) {
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
    std::fprintf(stderr, "volstream: %s (--help lists the options)\n", message.c_str());
    return 2;
  } catch (const vs::InputError& e) {
    std::fprintf(stderr, "volstream: %s: %s\n", e.file().c_str(), e.what());
    return 2;
  } catch (const vs::UsageError& e) {
    std::fprintf(stderr, "volstream: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "volstream: out of memory\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "volstream: %s\n", e.what());
    return 1;
  }
  return 0;
}
