#include "io/restart.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "version.hpp"

namespace narwhal {
namespace {

constexpr const char* kFormat = "narwhal-restart-2";
// cfl_control: reference norm, last CFL, recovering, the rise guard's ceiling, its two
// recent norms, armed.
constexpr hsize_t kCflControlLength = 7;
constexpr std::size_t kUserBlock = 4096;  // HDF5 user blocks are powers of two >= 512
constexpr std::size_t kMaxChunks = 400;   // keeps the CRC list inside the user block

// ---- checksums over the bytes after the user block --------------------------------

std::size_t chunk_size_for(std::size_t payload) {
  const std::size_t min_chunk = 64 * 1024;
  const std::size_t c = (payload + kMaxChunks - 1) / kMaxChunks;
  return std::max(min_chunk, (c + 4095) / 4096 * 4096);
}

std::vector<uLong> chunk_crcs(const std::vector<char>& bytes, std::size_t chunk) {
  std::vector<uLong> crcs;
  for (std::size_t at = kUserBlock; at < bytes.size(); at += chunk) {
    const std::size_t n = std::min(chunk, bytes.size() - at);
    crcs.push_back(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n)));
  }
  return crcs;
}

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("restart file '{}' cannot be opened", path);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string header_text(std::size_t file_size, std::size_t chunk, const std::vector<uLong>& crcs) {
  std::string h = fmt::format("{}\nbytes {}\nchunk {}\ncrc32", kFormat, file_size, chunk);
  for (uLong c : crcs) h += fmt::format(" {:08x}", c);
  h += "\n";
  return h;
}

void verify(const std::string& path, const std::vector<char>& bytes) {
  if (bytes.size() < kUserBlock)
    fail("restart '{}': {} bytes, shorter than its {}-byte header (bytes 0 to {}): truncated or not a narwhal "
         "restart", path, bytes.size(), kUserBlock, kUserBlock - 1);
  const auto end = std::find(bytes.begin(), bytes.begin() + kUserBlock, '\0');
  const std::string header(bytes.begin(), end);
  std::istringstream in(header);
  std::string format, w_bytes, w_chunk, w_crc;
  std::size_t size = 0, chunk = 0;
  std::getline(in, format);
  if (format != kFormat)
    fail("restart '{}': byte 0: not a {} file (first line '{}'); restarts from other formats or versions are "
         "not read", path, kFormat, format.substr(0, 40));
  if (!(in >> w_bytes >> size >> w_chunk >> chunk >> w_crc) || w_bytes != "bytes" || w_chunk != "chunk" ||
      w_crc != "crc32" || chunk == 0)
    fail("restart '{}': bytes 0 to {}: the checksum header is corrupt", path, kUserBlock - 1);
  if (size != bytes.size())
    fail("restart '{}': the file has {} bytes, its header (bytes 0 to {}) says {}: truncated or appended to", path,
         bytes.size(), kUserBlock - 1, size);
  std::vector<uLong> stored;
  for (std::string word; in >> word;) {
    uLong v = 0;
    std::size_t used = 0;
    try {
      v = std::stoul(word, &used, 16);
    } catch (const std::exception&) {
      used = 0;
    }
    if (word.size() != 8 || used != 8)
      fail("restart '{}': bytes 0 to {}: the checksum header is corrupt (entry '{}')", path, kUserBlock - 1, word);
    stored.push_back(v);
  }
  if (header.back() != '\n')
    fail("restart '{}': bytes 0 to {}: the checksum header is corrupt (no final line end)", path, kUserBlock - 1);
  for (auto it = end; it != bytes.begin() + kUserBlock; ++it)
    if (*it != '\0')
      fail("restart '{}': byte {} of the header block is not zero: the file is corrupt", path, it - bytes.begin());
  const std::vector<uLong> computed = chunk_crcs(bytes, chunk);
  if (computed.size() != stored.size())
    fail("restart '{}': bytes 0 to {}: the header lists {} checksums for {} chunks: the file is corrupt", path,
         kUserBlock - 1, stored.size(), computed.size());
  for (std::size_t c = 0; c < computed.size(); ++c)
    if (computed[c] != stored[c]) {
      const std::size_t lo = kUserBlock + c * chunk, hi = std::min(bytes.size(), lo + chunk) - 1;
      fail("restart '{}': bytes {} to {} do not match their checksum: the file is corrupt", path, lo, hi);
    }
}

// ---- HDF5 helpers: every call checked, errors name the file and the object --------

struct Hid {  // closes an HDF5 handle on scope exit
  hid_t id;
  herr_t (*close)(hid_t);
  ~Hid() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

void write_string_attr(const std::string& path, hid_t obj, const char* name, const std::string& value) {
  Hid type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type, std::max<std::size_t>(1, value.size()));
  Hid space{H5Screate(H5S_SCALAR), H5Sclose};
  Hid attr{H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (attr < 0 || H5Awrite(attr, type, value.empty() ? "" : value.c_str()) < 0)
    fail("cannot write attribute '{}' of restart file '{}'", name, path);
}

std::string read_string_attr(const std::string& path, hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) fail("restart '{}': attribute '{}' is missing", path, name);
  Hid attr{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  Hid type{H5Aget_type(attr), H5Tclose};
  if (H5Tget_class(type) != H5T_STRING) fail("restart '{}': attribute '{}' is not a string", path, name);
  std::string v(H5Tget_size(type), '\0');
  if (H5Aread(attr, type, v.data()) < 0) fail("restart '{}': attribute '{}' cannot be read", path, name);
  v.erase(std::find(v.begin(), v.end(), '\0'), v.end());
  return v;
}

template <class T>
void write_scalar_attr(const std::string& path, hid_t obj, const char* name, hid_t type, T value) {
  Hid space{H5Screate(H5S_SCALAR), H5Sclose};
  Hid attr{H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (attr < 0 || H5Awrite(attr, type, &value) < 0) fail("cannot write attribute '{}' of restart file '{}'", name, path);
}

template <class T>
T read_scalar_attr(const std::string& path, hid_t obj, const char* name, hid_t type) {
  if (H5Aexists(obj, name) <= 0) fail("restart '{}': attribute '{}' is missing", path, name);
  T v{};
  Hid attr{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  Hid space{H5Aget_space(attr), H5Sclose};
  if (H5Sget_simple_extent_npoints(space) != 1 || H5Aread(attr, type, &v) < 0)
    fail("restart '{}': attribute '{}' cannot be read as one value", path, name);
  return v;
}

void write_dataset(const std::string& path, hid_t grp, const char* name, const std::vector<hsize_t>& dims,
                   const double* data) {
  Hid space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
  Hid ds{H5Dcreate2(grp, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (ds < 0 || H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail("cannot write dataset '{}' of restart file '{}'", name, path);
}

// Reads a double dataset after checking that its shape is `dims`.
// The length of a one-dimensional dataset (an error naming it otherwise).
hsize_t dataset_length(const std::string& path, hid_t file, const std::string& name) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) fail("restart '{}': dataset '{}' is missing", path, name);
  Hid ds{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  Hid space{H5Dget_space(ds), H5Sclose};
  if (H5Sget_simple_extent_ndims(space) != 1) fail("restart '{}': dataset '{}' is not one-dimensional", path, name);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  return n;
}

void read_dataset(const std::string& path, hid_t file, const std::string& name, const std::vector<hsize_t>& dims,
                  std::vector<double>& out) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) fail("restart '{}': dataset '{}' is missing", path, name);
  Hid ds{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  Hid space{H5Dget_space(ds), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> have(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space, have.data(), nullptr);
  auto shape = [](const std::vector<hsize_t>& d) {
    std::string s;
    for (hsize_t x : d) {
      if (!s.empty()) s += 'x';
      s += std::to_string(x);
    }
    return s;
  };
  if (have != dims)
    fail("restart '{}': dataset '{}' has shape {}, this run needs {}", path, name, shape(have), shape(dims));
  std::size_t n = 1;
  for (hsize_t x : dims) n *= x;
  out.resize(n);
  if (H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail("restart '{}': dataset '{}' cannot be read", path, name);
}

void write_text_dataset(const std::string& path, hid_t file, const char* name, const std::string& text) {
  // A dataset, not an attribute: attributes are limited to 64 KiB, case files are not.
  Hid type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type, std::max<std::size_t>(1, text.size()));
  Hid space{H5Screate(H5S_SCALAR), H5Sclose};
  Hid ds{H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (ds < 0 || H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.empty() ? "" : text.c_str()) < 0)
    fail("cannot write dataset '{}' of restart file '{}'", name, path);
}

template <class State, int N>
void pack(const Block& b, const GhostArray<State>& a, std::vector<double>& buf) {
  buf.clear();
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i)
        for (int m = 0; m < N; ++m) buf.push_back(a(i, j, k)[m]);
}

template <class State, int N>
void unpack(const Block& b, const std::vector<double>& buf, GhostArray<State>& a) {
  std::size_t n = 0;
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i)
        for (int m = 0; m < N; ++m) a(i, j, k)[m] = buf[n++];
}

void write_hdf5(const std::string& path, const Grid& g, const FlowField& f, const RestartInfo& info,
                const std::string& case_text, const FlowField* previous) {
  Hid fcpl{H5Pcreate(H5P_FILE_CREATE), H5Pclose};
  H5Pset_userblock(fcpl, kUserBlock);
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  if (file < 0) fail("cannot create restart file '{}'", path);
  try {
    write_string_attr(path, file, "format", kFormat);
    write_string_attr(path, file, "version", kVersion);
    write_string_attr(path, file, "git_sha", kGitSha);
    write_string_attr(path, file, "turbulence_model", info.turbulence_model);
    write_text_dataset(path, file, "case", case_text);
    write_scalar_attr(path, file, "iteration", H5T_NATIVE_INT, info.iteration);
    write_scalar_attr(path, file, "wall_seconds", H5T_NATIVE_DOUBLE, info.wall_seconds);
    write_scalar_attr(path, file, "turbulence_reference_0", H5T_NATIVE_DOUBLE, info.turbulence_reference[0]);
    write_scalar_attr(path, file, "turbulence_reference_1", H5T_NATIVE_DOUBLE, info.turbulence_reference[1]);
    write_scalar_attr(path, file, "body_force", H5T_NATIVE_DOUBLE, info.body_force);
    write_scalar_attr(path, file, "stall_anchor", H5T_NATIVE_DOUBLE, info.stall_anchor);
    write_scalar_attr(path, file, "stall_anchor_iteration", H5T_NATIVE_INT, info.stall_anchor_iteration);
    if (!info.force_window.empty()) {
      write_scalar_attr(path, file, "force_components", H5T_NATIVE_INT, info.force_components);
      write_dataset(path, file, "force_window", {info.force_window.size()}, info.force_window.data());
    }
    if (!info.propulsor_state.empty())
      write_dataset(path, file, "propulsor_state", {info.propulsor_state.size()}, info.propulsor_state.data());
    if (!info.control_state.empty())
      write_dataset(path, file, "control_state", {info.control_state.size()}, info.control_state.data());
    if (!info.body_state.empty())  // a free body's state (motion/coupled_body.hpp)
      write_dataset(path, file, "body_state", {info.body_state.size()}, info.body_state.data());
    write_scalar_attr(path, file, "turbulence_starting", H5T_NATIVE_INT, info.turbulence_starting ? 1 : 0);
    const CflControlState& cfl = info.cfl_control;
    const std::array<double, kCflControlLength> control{cfl.reference_norm,        cfl.last_cfl,
                                                        cfl.recovering ? 1.0 : 0.0, cfl.rise_guard.ceiling,
                                                        cfl.rise_guard.recent[0],   cfl.rise_guard.recent[1],
                                                        cfl.rise_guard.armed ? 1.0 : 0.0};
    write_dataset(path, file, "cfl_control", {control.size()}, control.data());
    write_scalar_attr(path, file, "turbulence_start_ended", H5T_NATIVE_INT, info.turbulence_start_ended);
    if (!info.start_window.empty()) {
      write_scalar_attr(path, file, "start_components", H5T_NATIVE_INT, info.start_components);
      write_dataset(path, file, "start_window", {info.start_window.size()}, info.start_window.data());
    }
    const std::array<double, 14> monitors{info.residual[0], info.residual[1], info.residual[2], info.residual[3],
                                          info.residual_total, info.cfl, info.residual_drop,
                                          info.turbulence_residual[0], info.turbulence_residual[1],
                                          info.turbulence_drop, info.residual_reference[0],
                                          info.residual_reference[1], info.residual_reference[2],
                                          info.residual_reference[3]};
    write_dataset(path, file, "last_iteration", {monitors.size()}, monitors.data());
    write_scalar_attr(path, file, "time_step", H5T_NATIVE_INT, info.time_step);
    write_scalar_attr(path, file, "time", H5T_NATIVE_DOUBLE, info.time);
    write_scalar_attr(path, file, "time_step_size", H5T_NATIVE_DOUBLE, info.time_step_size);
    write_scalar_attr(path, file, "block_count", H5T_NATIVE_INT, static_cast<int>(g.blocks.size()));
    write_scalar_attr(path, file, "turbulence_variables", H5T_NATIVE_INT, f.turb.empty() ? 0 : 2);
    Hid blocks{H5Gcreate2(file, "blocks", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    std::vector<double> buf;
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
      const Block& b = g.blocks[ib];
      Hid grp{H5Gcreate2(blocks, b.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
      if (grp < 0) fail("cannot write block '{}' of restart file '{}'", b.name, path);
      const std::array<double, 6> e = info.reference_extents.empty() ? node_extent(b) : info.reference_extents[ib];
      write_dataset(path, grp, "extent", {6}, e.data());
      // Q[k][j][i][eq] (C order, i fastest among cells, equations innermost).
      const std::vector<hsize_t> dims{static_cast<hsize_t>(b.nk), static_cast<hsize_t>(b.nj),
                                      static_cast<hsize_t>(b.ni), kNumEq};
      pack<State, kNumEq>(b, f.Q[ib], buf);
      write_dataset(path, grp, "Q", dims, buf.data());
      if (previous) {  // Q^{n-1} of a dual-time run
        pack<State, kNumEq>(b, previous->Q[ib], buf);
        write_dataset(path, grp, "Q_previous", dims, buf.data());
      }
      if (!f.turb.empty()) {  // turbulence model variables T[k][j][i][2]
        pack<TurbState, 2>(b, f.turb[ib], buf);
        write_dataset(path, grp, "turbulence", {dims[0], dims[1], dims[2], 2}, buf.data());
        if (previous) {  // and their level n-1 in a dual-time run
          if (previous->turb.size() != g.blocks.size())
            fail("restart '{}': the turbulence variables' level n-1 is missing (a dual-time run keeps it)", path);
          pack<TurbState, 2>(b, previous->turb[ib], buf);
          write_dataset(path, grp, "turbulence_previous", {dims[0], dims[1], dims[2], 2}, buf.data());
        }
      }
    }
  } catch (...) {
    H5Fclose(file);
    throw;
  }
  if (H5Fclose(file) < 0) fail("error closing restart file '{}' (disk full?)", path);
}

// The CFL controller's state: the dataset cfl_control, or the pieces older restarts kept
// (the reference norm as an attribute, the last CFL as the monitors', then a cut flag and
// the rise guard's dataset), each missing piece as a run that never had it.
CflControlState read_cfl_control(const std::string& path, hid_t file, Real monitors_cfl) {
  CflControlState c;
  if (H5Lexists(file, "cfl_control", H5P_DEFAULT) > 0) {
    std::vector<Real> v;
    read_dataset(path, file, "cfl_control", {kCflControlLength}, v);
    c.reference_norm = v[0];
    c.last_cfl = v[1];
    c.recovering = v[2] != 0.0;
    c.rise_guard.ceiling = v[3];
    c.rise_guard.recent = {v[4], v[5]};
    c.rise_guard.armed = v[6] != 0.0;
    return c;
  }
  c.reference_norm = read_scalar_attr<double>(path, file, "reference_norm", H5T_NATIVE_DOUBLE);
  c.last_cfl = monitors_cfl;
  if (H5Aexists(file, "cfl_recovering") > 0)
    c.recovering = read_scalar_attr<int>(path, file, "cfl_recovering", H5T_NATIVE_INT) != 0;
  if (H5Lexists(file, "cfl_rise_guard", H5P_DEFAULT) > 0) {
    std::vector<Real> guard;
    read_dataset(path, file, "cfl_rise_guard", {4}, guard);
    c.rise_guard.ceiling = guard[0];
    c.rise_guard.recent = {guard[1], guard[2]};
    c.rise_guard.armed = guard[3] != 0.0;
  }
  return c;
}

void stamp_checksums(const std::string& path) {
  const std::vector<char> bytes = read_bytes(path);
  const std::size_t chunk = chunk_size_for(bytes.size() - kUserBlock);
  const std::string h = header_text(bytes.size(), chunk, chunk_crcs(bytes, chunk));
  if (h.size() >= kUserBlock) fail("restart '{}': checksum header too long", path);
  const int fd = ::open(path.c_str(), O_WRONLY);
  if (fd < 0) fail("cannot open restart file '{}' to stamp its checksums: {}", path, std::strerror(errno));
  std::string block(kUserBlock, '\0');
  std::copy(h.begin(), h.end(), block.begin());
  const bool ok = ::pwrite(fd, block.data(), block.size(), 0) == static_cast<ssize_t>(block.size()) && ::fsync(fd) == 0;
  const int err = errno;
  ::close(fd);
  if (!ok) fail("cannot write restart file '{}': {}", path, std::strerror(err));
}

}  // namespace

void write_restart(const std::string& path, const Grid& g, const FlowField& f, const RestartInfo& info,
                   const std::string& case_text, const FlowField* previous) {
  const std::string tmp = path + ".tmp";
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures are reported as Errors, not HDF5 stacks
  write_hdf5(tmp, g, f, info, case_text, previous);
  stamp_checksums(tmp);
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) fail("cannot move restart file '{}' to '{}': {}", tmp, path, ec.message());
}

void stamp_restart_checksums(const std::string& path) { stamp_checksums(path); }

void verify_restart_checksums(const std::string& path) { verify(path, read_bytes(path)); }

RestartInfo read_restart(const std::string& path, const Grid& g, FlowField& f, const std::string& turbulence_model,
                         FlowField* previous) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail("restart file '{}' does not exist or is not a file", path);
  verify_restart_checksums(path);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  Hid file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (file < 0) fail("restart file '{}' is not a readable HDF5 file", path);
  RestartInfo info;
  info.turbulence_model = read_string_attr(path, file, "turbulence_model");
  if (info.turbulence_model != turbulence_model)
    fail("restart '{}' was written by a run with turbulence model '{}'; this run uses '{}'", path,
         info.turbulence_model, turbulence_model);
  info.iteration = read_scalar_attr<int>(path, file, "iteration", H5T_NATIVE_INT);
  if (info.iteration < 0) fail("restart '{}': attribute 'iteration' is negative ({})", path, info.iteration);
  info.wall_seconds = read_scalar_attr<double>(path, file, "wall_seconds", H5T_NATIVE_DOUBLE);
  info.body_force = read_scalar_attr<double>(path, file, "body_force", H5T_NATIVE_DOUBLE);
  if (H5Aexists(file, "stall_anchor") > 0) {  // older restarts: the detector starts afresh
    info.stall_anchor = read_scalar_attr<double>(path, file, "stall_anchor", H5T_NATIVE_DOUBLE);
    info.stall_anchor_iteration = read_scalar_attr<int>(path, file, "stall_anchor_iteration", H5T_NATIVE_INT);
  }
  if (H5Aexists(file, "force_components") > 0) {  // written only by runs that test their forces' steadiness
    info.force_components = read_scalar_attr<int>(path, file, "force_components", H5T_NATIVE_INT);
    const hsize_t n = dataset_length(path, file, "force_window");
    read_dataset(path, file, "force_window", {n}, info.force_window);
  }
  if (H5Lexists(file, "propulsor_state", H5P_DEFAULT) > 0) {
    const hsize_t n = dataset_length(path, file, "propulsor_state");
    read_dataset(path, file, "propulsor_state", {n}, info.propulsor_state);
  }
  if (H5Lexists(file, "control_state", H5P_DEFAULT) > 0) {
    const hsize_t n = dataset_length(path, file, "control_state");
    read_dataset(path, file, "control_state", {n}, info.control_state);
  }
  if (H5Lexists(file, "body_state", H5P_DEFAULT) > 0) {
    const hsize_t n = dataset_length(path, file, "body_state");
    read_dataset(path, file, "body_state", {n}, info.body_state);
  }
  if (H5Aexists(file, "turbulence_starting") > 0) {  // older restarts: past any start
    info.turbulence_starting = read_scalar_attr<int>(path, file, "turbulence_starting", H5T_NATIVE_INT) != 0;
    info.turbulence_start_ended = read_scalar_attr<int>(path, file, "turbulence_start_ended", H5T_NATIVE_INT);
  }
  if (H5Aexists(file, "start_components") > 0) {
    info.start_components = read_scalar_attr<int>(path, file, "start_components", H5T_NATIVE_INT);
    const hsize_t n = dataset_length(path, file, "start_window");
    read_dataset(path, file, "start_window", {n}, info.start_window);
  }
  info.turbulence_reference[0] = read_scalar_attr<double>(path, file, "turbulence_reference_0", H5T_NATIVE_DOUBLE);
  info.turbulence_reference[1] = read_scalar_attr<double>(path, file, "turbulence_reference_1", H5T_NATIVE_DOUBLE);
  std::vector<double> m;
  // res_p, res_u, res_v, res_w, total, cfl, drop, turbulence residuals (2), turbulence drop,
  // the largest res_p, res_u, res_v, res_w so far
  read_dataset(path, file, "last_iteration", {14}, m);
  info.residual = {m[0], m[1], m[2], m[3]};
  info.residual_total = m[4];
  info.cfl = m[5];
  info.cfl_control = read_cfl_control(path, file, info.cfl);
  info.residual_drop = m[6];
  info.turbulence_residual = {m[7], m[8]};
  info.turbulence_drop = m[9];
  info.residual_reference = {m[10], m[11], m[12], m[13]};
  if (H5Aexists(file, "time_step") > 0) {  // older restarts: steady states
    info.time_step = read_scalar_attr<int>(path, file, "time_step", H5T_NATIVE_INT);
    info.time = read_scalar_attr<double>(path, file, "time", H5T_NATIVE_DOUBLE);
    info.time_step_size = read_scalar_attr<double>(path, file, "time_step_size", H5T_NATIVE_DOUBLE);
  }
  if (info.time_step > 0 && !previous)
    fail("restart '{}' holds a dual-time run at step {} (t = {:g}); this case has no [time] table to continue it",
         path, info.time_step, info.time);
  const int blocks = read_scalar_attr<int>(path, file, "block_count", H5T_NATIVE_INT);
  if (blocks != static_cast<int>(g.blocks.size()))
    fail("restart '{}' holds {} block(s); this run's grid has {}: it was written for another grid", path, blocks,
         g.blocks.size());
  // Transport models keep two variables per cell; algebraic ones (Baldwin-Lomax) none.
  const int variables = read_scalar_attr<int>(path, file, "turbulence_variables", H5T_NATIVE_INT);
  if (variables != 0 && variables != 2)
    fail("restart '{}': attribute 'turbulence_variables' is {}, expected 0 or 2", path, variables);
  const bool turbulent = variables == 2;
  if (turbulent && f.turb.size() != g.blocks.size()) f.allocate_turbulence(g);
  std::vector<double> buf;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    const std::string grp = "blocks/" + b.name;
    if (H5Lexists(file, "blocks", H5P_DEFAULT) <= 0 || H5Lexists(file, grp.c_str(), H5P_DEFAULT) <= 0)
      fail("restart '{}' has no block '{}': it was written for another grid", path, b.name);
    read_dataset(path, file, grp + "/extent", {6}, buf);
    const std::array<double, 6> e = node_extent(b);
    const double scale = std::max({e[3] - e[0], e[4] - e[1], e[5] - e[2]});
    for (int d = 0; d < 6; ++d)
      if (!(std::abs(buf[d] - e[d]) <= 1e-9 * scale))
        fail("restart '{}': block '{}' spans [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}], this run's "
             "block [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}]: it was written for another grid",
             path, b.name, buf[0], buf[3], buf[1], buf[4], buf[2], buf[5], e[0], e[3], e[1], e[4], e[2], e[5]);
    const std::vector<hsize_t> dims{static_cast<hsize_t>(b.nk), static_cast<hsize_t>(b.nj),
                                    static_cast<hsize_t>(b.ni), kNumEq};
    read_dataset(path, file, grp + "/Q", dims, buf);
    unpack<State, kNumEq>(b, buf, f.Q[ib]);
    if (info.time_step > 0) {
      read_dataset(path, file, grp + "/Q_previous", dims, buf);
      unpack<State, kNumEq>(b, buf, previous->Q[ib]);
    }
    if (turbulent) {
      read_dataset(path, file, grp + "/turbulence", {dims[0], dims[1], dims[2], 2}, buf);
      unpack<TurbState, 2>(b, buf, f.turb[ib]);
      if (info.time_step > 0) {
        if (previous->turb.size() != g.blocks.size()) previous->allocate_turbulence(g);
        read_dataset(path, file, grp + "/turbulence_previous", {dims[0], dims[1], dims[2], 2}, buf);
        unpack<TurbState, 2>(b, buf, previous->turb[ib]);
      }
    }
  }
  return info;
}

}  // namespace narwhal
