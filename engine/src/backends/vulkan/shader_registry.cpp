// The only translation unit that includes the generated SPIR-V headers (shaders/CMakeLists.txt
// makes it depend on them).
#include "backends/vulkan/shader_registry.hpp"

#include "expanse_spirv/audit_spv.h"
#include "expanse_spirv/blocks_spv.h"
#include "expanse_spirv/bucket_spv.h"
#include "expanse_spirv/predicate_test_spv.h"
#include "expanse_spirv/prepare_sites_spv.h"
#include "expanse_spirv/radix_sort_spv.h"
#include "expanse_spirv/scan_spv.h"
#include "expanse_spirv/star_links_spv.h"
#include "expanse_spirv/star_spv.h"

namespace expanse::detail::vk::spirv {

std::span<const std::uint32_t> star() { return expanse_spirv_star; }
std::span<const std::uint32_t> star_links() { return expanse_spirv_star_links; }
std::span<const std::uint32_t> blocks() { return expanse_spirv_blocks; }
std::span<const std::uint32_t> predicate_test() { return expanse_spirv_predicate_test; }
std::span<const std::uint32_t> bucket() { return expanse_spirv_bucket; }
std::span<const std::uint32_t> scan() { return expanse_spirv_scan; }
std::span<const std::uint32_t> audit() { return expanse_spirv_audit; }
std::span<const std::uint32_t> prepare_sites() { return expanse_spirv_prepare_sites; }
std::span<const std::uint32_t> radix_sort() { return expanse_spirv_radix_sort; }

}  // namespace expanse::detail::vk::spirv
