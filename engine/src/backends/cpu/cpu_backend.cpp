#include "backends/backend.hpp"

namespace expanse::detail {
namespace {

// The CPU backend leaves the whole triangulation to the seam stage, seeded with one seed: the
// paper's sequential algorithm. One algorithm, three executors.
class CpuBackend final : public Backend {
 public:
  BackendKind kind() const override { return BackendKind::cpu; }
  std::string device_name() const override { return "CPU (sequential)"; }
  GrowResult grow(const GrowInput&) override { return {}; }
};

}  // namespace

std::unique_ptr<Backend> make_cpu_backend() { return std::make_unique<CpuBackend>(); }

}  // namespace expanse::detail
