// `expanse info`: the backends compiled into this binary and the devices each one sees.
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "expanse/triangulate.hpp"

namespace expanse::cli {
namespace {

int run_info(bool json) {
  const auto backends = describe_backends();
  const BackendKind automatic = default_backend();
  if (json) {
    nlohmann::json out;
    out["version"] = EXPANSE_VERSION;
    out["default_backend"] = std::string(to_string(automatic));
    out["backends"] = nlohmann::json::array();
    for (const BackendDescription& b : backends) {
      nlohmann::json entry{{"name", std::string(to_string(b.kind))},
                           {"compiled", b.compiled},
                           {"unavailable", b.unavailable},
                           {"devices", nlohmann::json::array()}};
      for (const DeviceDescription& d : b.devices) {
        entry["devices"].push_back({{"index", d.index}, {"name", d.name}, {"type", d.type},
                                    {"fp64", d.fp64}, {"details", d.details}});
      }
      out["backends"].push_back(entry);
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("expanse %s\ndefault backend: %s\n", EXPANSE_VERSION, std::string(to_string(automatic)).c_str());
  for (const BackendDescription& b : backends) {
    const std::string name(to_string(b.kind));
    if (!b.compiled) {
      std::printf("%-7s not compiled in\n", name.c_str());
      continue;
    }
    if (b.devices.empty()) {
      std::printf("%-7s compiled in, no usable device%s%s\n", name.c_str(),
                  b.unavailable.empty() ? "" : ": ", b.unavailable.c_str());
      continue;
    }
    std::printf("%-7s compiled in, %zu device%s\n", name.c_str(), b.devices.size(),
                b.devices.size() == 1 ? "" : "s");
    for (const DeviceDescription& d : b.devices) {
      std::printf("  [%d] %s (%s, fp64 %s)%s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                  d.fp64 ? "yes" : "no", d.details.empty() ? "" : ": ", d.details.c_str());
    }
  }
  return 0;
}

}  // namespace

Command add_info_command(CLI::App& parent) {
  auto json = std::make_shared<bool>(false);
  CLI::App* app = parent.add_subcommand("info", "list the backends compiled in and their devices");
  app->add_flag("--json", *json, "print one JSON object instead of text");
  return {app, [json] { return run_info(*json); }};
}

}  // namespace expanse::cli
