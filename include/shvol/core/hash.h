#pragma once
/// \file FNV-1a, 64 bit (Fowler, Noll & Vo): a fast, non-cryptographic hash for identifying
/// renders and input files. h ← (h ⊕ byte) · 1099511628211, from h₀ = 14695981039346656037.
#include <cstddef>
#include <cstdint>
#include <string>

namespace shvol {

constexpr uint64_t kFnv1aOffset = 14695981039346656037ull;  // 0xcbf29ce484222325

/// Continues the hash h over n bytes (start with kFnv1aOffset).
inline uint64_t fnv1a(const void* data, size_t n, uint64_t h = kFnv1aOffset) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

/// 16 lowercase hex digits.
std::string hexHash(uint64_t h);

}  // namespace shvol
