#include "sim/hdf5/file_seal.h"

#include <algorithm>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "sim/experiment/config_error.h"

namespace mcref {

namespace {

constexpr char kHdf5Signature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};

// 64-bit FNV-1a over 8-byte words of the file from `from` to its end; `bytes` is the file size.
std::uint64_t digest(std::istream& in, std::uint64_t from, std::uint64_t& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  in.seekg(static_cast<std::streamoff>(from));
  std::vector<char> buf(1 << 20);
  bytes = from;
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const std::size_t got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    bytes += got;
    std::memset(buf.data() + got, 0, (8 - got % 8) % 8);  // zero-pad the tail word
    for (std::size_t i = 0; i < got; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, buf.data() + i, 8);
      h = (h ^ w) * 0x100000001b3ull;
    }
  }
  return h;
}

std::string seal_line(std::uint64_t bytes, std::uint64_t h) {
  char line[96];
  std::snprintf(line, sizeof line, "mcref-seal 1 bytes=%" PRIu64 " fnv1a64=%016" PRIx64 "\n", bytes, h);
  return line;
}

}  // namespace

std::string content_digest(const std::string& bytes) {
  std::istringstream in(bytes);
  std::uint64_t n = 0;
  const std::uint64_t h = digest(in, 0, n);
  char line[64];
  std::snprintf(line, sizeof line, "bytes=%" PRIu64 " fnv1a64=%016" PRIx64, n, h);
  return line;
}

void seal_file(const std::string& path) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot reopen to seal it");
  std::uint64_t bytes = 0;
  const std::uint64_t h = digest(f, kSealBlockBytes, bytes);
  f.clear();
  std::string block = seal_line(bytes, h);
  block.resize(kSealBlockBytes, '\0');
  f.seekp(0);
  f.write(block.data(), static_cast<std::streamsize>(block.size()));
  f.flush();
  if (!f) throw std::runtime_error(path + ": writing its seal failed");
}

bool check_seal(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ConfigError(path, "", "is a directory, not a file");
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ConfigError(path, "", "is not a regular file");  // (a FIFO would block the read)
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, "", "cannot be read");
  std::string block(kSealBlockBytes, '\0');
  in.read(block.data(), kSealBlockBytes);
  const std::size_t got = static_cast<std::size_t>(in.gcount());
  if (got >= 8 && std::memcmp(block.data(), kHdf5Signature, 8) == 0) return false;  // no user block
  if (got < kSealBlockBytes || block.compare(0, 13, "mcref-seal 1 ") != 0) {
    char next[8] = {};
    in.read(next, 8);
    if (in.gcount() == 8 && std::memcmp(next, kHdf5Signature, 8) == 0)
      throw ConfigError(path, "", "is damaged: its seal (the first line of the file) is missing or overwritten");
    throw ConfigError(path, "", "not an HDF5 file");
  }
  in.clear();
  std::uint64_t bytes = 0;
  const std::uint64_t h = digest(in, kSealBlockBytes, bytes);
  const std::string expect = seal_line(bytes, h);
  std::string padded = expect;
  padded.resize(kSealBlockBytes, '\0');
  if (block != padded) {
    std::string stored = block.substr(0, std::min<std::size_t>(block.find('\n'), 64));
    for (char& c : stored)
      if (c < ' ' || c > '~') c = '?';
    throw ConfigError(path, "", "is damaged: its bytes no longer match the seal written with it (seal: \"" + stored +
                                    "\"; now " + expect.substr(0, expect.size() - 1) +
                                    "). It was truncated, corrupted or edited by another tool");
  }
  return true;
}

}  // namespace mcref
