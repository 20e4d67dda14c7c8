// `expanse`: generate point sets, triangulate Triangle .node files, list backends.
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "expanse/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Expanse: exact 2D Delaunay triangulation on GPUs", "expanse"};
  app.set_version_flag("--version", "expanse " EXPANSE_VERSION);
  app.require_subcommand(1);
  std::vector<expanse::cli::Command> commands = {
      expanse::cli::add_generate_command(app),
      expanse::cli::add_triangulate_command(app),
      expanse::cli::add_info_command(app),
  };
  CLI11_PARSE(app, argc, argv);

  try {
    for (const auto& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const expanse::Error& e) {
    // Messages already name the file and line, or the point; the code helps scripts and reports.
    std::fprintf(stderr, "expanse: error: %s [%s]\n", e.what(), expanse::to_string(e.code()));
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "expanse: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "expanse: error: %s\n", e.what());
    return 1;
  }
  return 1;
}
