#pragma once
// FNV-1a, 64 bit: the digest of checkpoints (their checksum and the run's fingerprint) and of
// a study's stage recipes. Not cryptographic: it finds damage and change, not tampering.
#include <cstddef>
#include <cstdint>

namespace tearflow {

/// FNV-1a 64 of `size` bytes, continuing from `hash` (for a digest of several pieces).
inline std::uint64_t fnv1a(const void* bytes, std::size_t size,
                           std::uint64_t hash = 0xcbf29ce484222325ULL) {
  const auto* p = static_cast<const unsigned char*>(bytes);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

} // namespace tearflow
