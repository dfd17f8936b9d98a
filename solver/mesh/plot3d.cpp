#include "mesh/plot3d.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace narwhal {
namespace {

// More blocks than any real grid has; a larger count is a corrupt header.
constexpr std::int64_t kMaxBlocks = 100000;

std::vector<char> slurp(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail("grid file '{}' is a directory", path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("grid file '{}' does not exist or cannot be read", path);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Text files hold printable characters and white space only; a binary file's
// leading integers (block count, dimensions) always contain control bytes.
bool is_text(const std::vector<char>& d) {
  const std::size_t n = std::min<std::size_t>(d.size(), 4096);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(d[i]);
    if (!(c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v' || (c >= 0x20 && c < 0x7f))) return false;
  }
  return true;
}

// Node counts of one block from the header, checked before anything is allocated.
Index3 checked_nodes(const std::string& path, int block, std::int64_t ni, std::int64_t nj, std::int64_t nk,
                     std::size_t header_offset) {
  if (ni < 2 || nj < 2 || nk < 2)
    fail("plot3d '{}': byte {}: block {} has {}x{}x{} nodes; each count must be >= 2", path, header_offset, block + 1,
         ni, nj, nk);
  check_block_size(fmt::format("plot3d '{}': byte {}: block {}", path, header_offset, block + 1), ni - 1, nj - 1,
                   nk - 1);
  return {static_cast<int>(ni), static_cast<int>(nj), static_cast<int>(nk)};
}

std::int64_t node_count(const Index3& n) { return std::int64_t{n[0]} * n[1] * n[2]; }

class TextScanner {
 public:
  TextScanner(const std::string& path, const std::vector<char>& d) : path_(path), d_(d) {}

  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return d_.size() - pos_; }

  // The next white-space separated token, or an empty view at the end of the file.
  std::string_view token() {
    while (pos_ < d_.size() && std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
    start_ = pos_;
    while (pos_ < d_.size() && !std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
    return {d_.data() + start_, pos_ - start_};
  }

  std::int64_t integer(const std::string& what) {
    const std::string_view t = token();
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty()) fail("plot3d '{}': truncated header: the file ends where {} should be", path_, what);
    if (ec != std::errc() || end != t.data() + t.size())
      fail("plot3d '{}': byte {}: expected {} (an integer), found '{}'", path_, start_, what, shorten(t));
    return v;
  }

  double coordinate(int block, int c, int i, int j, int k) {
    std::string_view t = token();
    if (t.empty())
      fail("plot3d '{}': truncated file: block {} coordinate {} ends at node ({}, {}, {})", path_, block + 1, "xyz"[c],
           i, j, k);
    // Fortran writes exponents as D; from_chars takes only e.
    char buf[64];
    if (t.size() < sizeof buf && t.find_first_of("dD") != std::string_view::npos) {
      std::memcpy(buf, t.data(), t.size());
      for (std::size_t m = 0; m < t.size(); ++m)
        if (buf[m] == 'd' || buf[m] == 'D') buf[m] = 'e';
      t = {buf, t.size()};
    }
    double v = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      fail("plot3d '{}': byte {}: block {} coordinate {} at node ({}, {}, {}): expected a finite number, found '{}'",
           path_, start_, block + 1, "xyz"[c], i, j, k, shorten(t));
    return v;
  }

 private:
  static std::string shorten(std::string_view t) {
    return t.size() > 40 ? std::string(t.substr(0, 40)) + "..." : std::string(t);
  }
  const std::string& path_;
  const std::vector<char>& d_;
  std::size_t pos_ = 0, start_ = 0;
};

std::vector<Block> read_ascii(const std::string& path, const std::vector<char>& d) {
  TextScanner in(path, d);
  const std::int64_t nb = in.integer("the block count");
  if (nb < 1 || nb > kMaxBlocks) fail("plot3d '{}': byte 0: block count {} is not between 1 and {}", path, nb, kMaxBlocks);
  std::vector<Index3> dims(static_cast<std::size_t>(nb));
  std::int64_t nodes = 0;
  for (int b = 0; b < nb; ++b) {
    const std::size_t at = in.offset();
    const std::int64_t ni = in.integer(fmt::format("block {} i-dimension", b + 1));
    const std::int64_t nj = in.integer(fmt::format("block {} j-dimension", b + 1));
    const std::int64_t nk = in.integer(fmt::format("block {} k-dimension", b + 1));
    dims[static_cast<std::size_t>(b)] = checked_nodes(path, b, ni, nj, nk, at);
    nodes += node_count(dims[static_cast<std::size_t>(b)]);
  }
  // Every coordinate takes at least one character and one separator: a header that
  // declares more than the file can hold is refused before the blocks are allocated.
  if (static_cast<std::int64_t>(in.remaining()) < 2 * 3 * nodes - 1)
    fail("plot3d '{}': truncated file: the header declares {} nodes ({} coordinates), but only {} bytes follow it",
         path, nodes, 3 * nodes, in.remaining());
  std::vector<Block> out;
  for (int b = 0; b < nb; ++b) {
    const Index3& n = dims[static_cast<std::size_t>(b)];
    Block blk(fmt::format("block{}", b + 1), n[0] - 1, n[1] - 1, n[2] - 1);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= blk.nk; ++k)
        for (int j = 0; j <= blk.nj; ++j)
          for (int i = 0; i <= blk.ni; ++i) blk.x(i, j, k)[c] = in.coordinate(b, c, i, j, k);
    out.push_back(std::move(blk));
  }
  if (!in.token().empty())
    fail("plot3d '{}': byte {}: unexpected data after the last block's coordinates", path, in.offset());
  return out;
}

template <class T>
T read_at(const std::vector<char>& d, std::size_t off) {
  T v;
  std::memcpy(&v, d.data() + off, sizeof(T));
  return v;
}

std::vector<Block> read_binary(const std::string& path, const std::vector<char>& d) {
  const std::int64_t size = static_cast<std::int64_t>(d.size());
  if (size < 16) fail("plot3d '{}': truncated file ({} bytes)", path, size);
  // Fortran unformatted: [4][nb][4][12*nb][dims][12*nb] then one record per block.
  const bool fortran = read_at<int32_t>(d, 0) == 4 && read_at<int32_t>(d, 8) == 4;
  std::int64_t off = fortran ? 4 : 0;
  const std::int64_t nb = read_at<int32_t>(d, static_cast<std::size_t>(off));
  if (nb < 1 || nb > kMaxBlocks)
    fail("plot3d '{}': byte {}: block count {} is not between 1 and {}", path, off, nb, kMaxBlocks);
  off += 4 + (fortran ? 8 : 0);
  if (size < off + 12 * nb + (fortran ? 4 : 0))
    fail("plot3d '{}': truncated header: {} blocks need {} bytes of dimensions from byte {}, the file has {} bytes",
         path, nb, 12 * nb, off, size);
  if (fortran && read_at<int32_t>(d, static_cast<std::size_t>(off - 4)) != 12 * nb)
    fail("plot3d '{}': byte {}: record marker {} does not match {} blocks (expected {})", path, off - 4,
         read_at<int32_t>(d, static_cast<std::size_t>(off - 4)), nb, 12 * nb);
  std::vector<Index3> dims(static_cast<std::size_t>(nb));
  std::int64_t nodes_total = 0;
  for (std::int64_t b = 0; b < nb; ++b) {
    const std::size_t at = static_cast<std::size_t>(off + 12 * b);
    dims[static_cast<std::size_t>(b)] = checked_nodes(path, static_cast<int>(b), read_at<int32_t>(d, at),
                                                      read_at<int32_t>(d, at + 4), read_at<int32_t>(d, at + 8), at);
    nodes_total += node_count(dims[static_cast<std::size_t>(b)]);
  }
  off += 12 * nb + (fortran ? 4 : 0);
  const std::int64_t markers = fortran ? 8 * nb : 0;
  const std::int64_t remaining = size - off;
  std::int64_t word = 0;
  if (remaining == 3 * nodes_total * 8 + markers) word = 8;
  else if (remaining == 3 * nodes_total * 4 + markers) word = 4;
  else
    fail("plot3d '{}': truncated or malformed file: {} bytes of coordinates from byte {}, expected {} (double) or {} "
         "(single) for {} nodes",
         path, remaining, off, 3 * nodes_total * 8 + markers, 3 * nodes_total * 4 + markers, nodes_total);
  std::vector<Block> out;
  for (std::int64_t b = 0; b < nb; ++b) {
    const Index3& n = dims[static_cast<std::size_t>(b)];
    const std::int64_t record = 3 * node_count(n) * word;
    if (fortran) {
      const std::int64_t head = read_at<int32_t>(d, static_cast<std::size_t>(off));
      const std::int64_t tail = read_at<int32_t>(d, static_cast<std::size_t>(off + 4 + record));
      if (head != record || tail != record)
        fail("plot3d '{}': byte {}: block {} record markers {} and {} do not match its {} bytes of coordinates", path,
             off, b + 1, head, tail, record);
      off += 4;
    }
    Block blk(fmt::format("block{}", b + 1), n[0] - 1, n[1] - 1, n[2] - 1);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= blk.nk; ++k)
        for (int j = 0; j <= blk.nj; ++j)
          for (int i = 0; i <= blk.ni; ++i) {
            const std::size_t at = static_cast<std::size_t>(off);
            const double v = word == 8 ? read_at<double>(d, at) : read_at<float>(d, at);
            if (!std::isfinite(v))
              fail("plot3d '{}': byte {}: block {} coordinate {} at node ({}, {}, {}) is {}", path, off, b + 1,
                   "xyz"[c], i, j, k, v);
            blk.x(i, j, k)[c] = v;
            off += word;
          }
    if (fortran) off += 4;
    out.push_back(std::move(blk));
  }
  return out;
}

}  // namespace

std::vector<Block> read_plot3d(const std::string& path) {
  const auto d = slurp(path);
  if (d.empty()) fail("plot3d '{}': the file is empty", path);
  return is_text(d) ? read_ascii(path, d) : read_binary(path, d);
}

void write_plot3d_ascii(const std::string& path, const std::vector<Block>& blocks) {
  std::ofstream out(path);
  out << blocks.size() << "\n";
  for (const auto& b : blocks) out << b.ni + 1 << " " << b.nj + 1 << " " << b.nk + 1 << "\n";
  out.precision(17);
  for (const auto& b : blocks)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) out << b.x(i, j, k)[c] << "\n";
  if (!out.flush()) fail("cannot write grid file '{}'", path);
}

void write_plot3d_fortran(const std::string& path, const std::vector<Block>& blocks) {
  std::ofstream out(path, std::ios::binary);
  auto w32 = [&](int32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  w32(4);
  w32(static_cast<int32_t>(blocks.size()));
  w32(4);
  w32(static_cast<int32_t>(12 * blocks.size()));
  for (const auto& b : blocks) {
    w32(b.ni + 1);
    w32(b.nj + 1);
    w32(b.nk + 1);
  }
  w32(static_cast<int32_t>(12 * blocks.size()));
  for (const auto& b : blocks) {
    const int32_t bytes = static_cast<int32_t>(3 * 8 * (b.ni + 1) * (b.nj + 1) * (b.nk + 1));
    w32(bytes);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) out.write(reinterpret_cast<const char*>(&b.x(i, j, k)[c]), 8);
    w32(bytes);
  }
  if (!out.flush()) fail("cannot write grid file '{}'", path);
}

}  // namespace narwhal
