#pragma once
// The seal of an mcref HDF5 file: a checksum of every byte, checked before
// HDF5 reads anything. HDF5 1.10 can crash or hang on damaged metadata
// (variable-length attributes above all), so a damaged file must never reach it.
//
// mcref files start with a 512-byte HDF5 user block, which HDF5 and every
// HDF5 tool skip. After the file is closed, the block receives one text line,
//   mcref-seal 1 bytes=<file size> fnv1a64=<16 hex digits>\n
// then zeros. The digest covers bytes [512, size): a 64-bit FNV-1a over
// 8-byte little-endian words (the tail zero-padded), so any change to one word
// always changes it. Editing a file with another HDF5 tool breaks the seal too.
#include <string>

namespace mcref {

constexpr int kSealBlockBytes = 512;  // the HDF5 user block (a power of two >= 512)

// "bytes=<n> fnv1a64=<16 hex digits>" of `bytes` (the seal's digest, from byte 0):
// names an input file's content in provenance.
std::string content_digest(const std::string& bytes);

// Writes the seal into the user block of the closed file `path` (std::runtime_error on I/O failure).
void seal_file(const std::string& path);

// Whether `path` is sealed and its seal matches. Throws ConfigError naming the
// file when the seal is present but wrong, or the user block is not a seal.
// Returns false for files without a user block (written before seals, or by
// another program): those are read unverified.
bool check_seal(const std::string& path);

}  // namespace mcref
