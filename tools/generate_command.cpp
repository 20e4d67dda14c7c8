// `expanse generate`: writes a deterministic point set as a Triangle .node file.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "expanse/generate.hpp"
#include "expanse/io.hpp"

namespace expanse::cli {
namespace {

struct GenerateArgs {
  std::string distribution = "uniform";
  std::size_t n = 1000;
  std::uint64_t seed = 1;
  std::string output;
  int first_index = 0;
};

std::string distribution_help() {
  std::string help = "point distribution:";
  for (const std::string& name : distribution_names()) {
    help += "\n  " + name + ": " + std::string(describe_distribution(name));
  }
  return help;
}

int run_generate(const GenerateArgs& args) {
  const auto points = generate_points(args.distribution, args.n, args.seed);
  write_node_file(args.output, points, args.first_index);
  std::fprintf(stderr, "expanse: wrote %zu %s points (seed %llu) to %s\n", points.size(),
               args.distribution.c_str(), static_cast<unsigned long long>(args.seed),
               args.output.c_str());
  return 0;
}

}  // namespace

Command add_generate_command(CLI::App& parent) {
  auto args = std::make_shared<GenerateArgs>();
  CLI::App* app = parent.add_subcommand("generate", "write a deterministic point set as a .node file");
  app->add_option("--dist,-d", args->distribution, distribution_help())->capture_default_str();
  app->add_option("-n", args->n, "number of points")->capture_default_str()->check(CLI::Range(0, 2147483647));
  app->add_option("--seed,-s", args->seed, "random seed (same seed, same points, on every platform)")
      ->capture_default_str();
  app->add_option("-o,--output", args->output, "output .node file")->required();
  app->add_option("--first-index", args->first_index, "number of the first vertex")
      ->capture_default_str()->check(CLI::IsMember({0, 1}));
  return {app, [args] { return run_generate(*args); }};
}

}  // namespace expanse::cli
