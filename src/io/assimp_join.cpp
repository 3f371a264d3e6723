// facet io: the pieces of assimp's join that are not templates (assimp_join.hpp).
#include "io/assimp_join.hpp"

#include <algorithm>
#include <unordered_map>

namespace facet::io_detail {

std::size_t reserved_buckets(std::size_t n) {
    // What reserve(n) does to an empty std::unordered_map (libstdc++ 12: rehash(ceil(n / 1.0f)),
    // which takes the rehash policy's next bucket count), without allocating the buckets.
    const std::__detail::_Prime_rehash_policy policy;
    const auto wanted = static_cast<std::size_t>(__builtin_ceil(static_cast<float>(n) / 1.0f));
    return policy._M_next_bkt(std::max(policy._M_bkt_for_elements(1), wanted));
}

bool assimp_equal(const JoinVertex& a, const JoinVertex& b, float margin) {
    return !((a.position - b.position).SquareLength() > margin) && !((a.normal - b.normal).SquareLength() > margin) &&
           !((a.uv - b.uv).SquareLength() > margin) && !((a.tangent - b.tangent).SquareLength() > margin) &&
           !((a.bitangent - b.bitangent).SquareLength() > margin);
}

}  // namespace facet::io_detail
