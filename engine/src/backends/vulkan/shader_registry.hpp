#pragma once
// SPIR-V of the kernels in shaders/, compiled at build time and embedded as uint32_t words.
#include <cstdint>
#include <span>

namespace expanse::detail::vk::spirv {

std::span<const std::uint32_t> star();
std::span<const std::uint32_t> star_links();
std::span<const std::uint32_t> blocks();
std::span<const std::uint32_t> predicate_test();
std::span<const std::uint32_t> bucket();
std::span<const std::uint32_t> scan();
std::span<const std::uint32_t> audit();
std::span<const std::uint32_t> prepare_sites();
std::span<const std::uint32_t> radix_sort();

}  // namespace expanse::detail::vk::spirv
