#pragma once
// The subcommands of `expanse`. Each one registers its options on the parent app and returns
// the action to run once parsing has succeeded; actions report failure by throwing.
#include <functional>

#include <CLI/CLI.hpp>

namespace expanse::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  ///< returns the process exit code
};

Command add_generate_command(CLI::App& parent);
Command add_triangulate_command(CLI::App& parent);
Command add_info_command(CLI::App& parent);

}  // namespace expanse::cli
