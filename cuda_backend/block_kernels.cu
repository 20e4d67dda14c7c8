// The paper's block layout: placeholder until implemented (see grow_paper_blocks).
#include "cuda_internal.hpp"

namespace expanse::detail::cuda {

void grow_paper_blocks(Context& ctx, const GrowInput& input, GrowResult& result) {
  (void)ctx, (void)input, (void)result;
  throw Error(ErrorCode::backend_unavailable, "CUDA backend: the paper's block layout is not implemented yet");
}

}  // namespace expanse::detail::cuda
