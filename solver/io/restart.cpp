#include "io/restart.hpp"

#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "version.hpp"

namespace narwhal {
namespace {

void write_string_attr(hid_t obj, const char* name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<std::size_t>(1, value.size()));
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, value.empty() ? "" : value.c_str());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

template <class T>
void write_scalar_attr(hid_t obj, const char* name, hid_t type, T value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, &value);
  H5Aclose(attr);
  H5Sclose(space);
}

template <class T>
T read_scalar_attr(hid_t obj, const char* name, hid_t type, const std::string& path) {
  if (H5Aexists(obj, name) <= 0) fail("restart '{}': attribute '{}' is missing", path, name);
  T v{};
  hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
  H5Aread(attr, type, &v);
  H5Aclose(attr);
  return v;
}

}  // namespace

void write_restart(const std::string& path, const Grid& g, const FlowField& f, const RestartInfo& info,
                   const std::string& case_text) {
  const std::string tmp = path + ".tmp";
  hid_t file = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) fail("cannot create restart file '{}'", tmp);
  write_string_attr(file, "format", "narwhal-restart-1");
  write_string_attr(file, "version", kVersion);
  write_string_attr(file, "git_sha", kGitSha);
  write_string_attr(file, "case", case_text);
  write_scalar_attr(file, "iteration", H5T_NATIVE_INT, info.iteration);
  write_scalar_attr(file, "reference_norm", H5T_NATIVE_DOUBLE, info.reference_norm);
  write_scalar_attr(file, "wall_seconds", H5T_NATIVE_DOUBLE, info.wall_seconds);
  write_scalar_attr(file, "turbulence_reference_0", H5T_NATIVE_DOUBLE, info.turbulence_reference[0]);
  write_scalar_attr(file, "turbulence_reference_1", H5T_NATIVE_DOUBLE, info.turbulence_reference[1]);
  write_scalar_attr(file, "body_force", H5T_NATIVE_DOUBLE, info.body_force);
  hid_t blocks = H5Gcreate2(file, "blocks", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<double> buf;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    hid_t grp = H5Gcreate2(blocks, b.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    // Dataset Q[k][j][i][eq] (C order, i fastest among cells, equations innermost).
    hsize_t dims[4] = {static_cast<hsize_t>(b.nk), static_cast<hsize_t>(b.nj), static_cast<hsize_t>(b.ni), kNumEq};
    buf.clear();
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i)
          for (int m = 0; m < kNumEq; ++m) buf.push_back(f.Q[ib](i, j, k)[m]);
    hid_t space = H5Screate_simple(4, dims, nullptr);
    hid_t ds = H5Dcreate2(grp, "Q", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
    write_string_attr(ds, "variables", "p,u,v,w");
    H5Dclose(ds);
    H5Sclose(space);
    if (!f.turb.empty()) {  // turbulence model variables T[k][j][i][2]
      hsize_t tdims[4] = {dims[0], dims[1], dims[2], 2};
      buf.clear();
      for (int k = 0; k < b.nk; ++k)
        for (int j = 0; j < b.nj; ++j)
          for (int i = 0; i < b.ni; ++i)
            for (int m = 0; m < 2; ++m) buf.push_back(f.turb[ib](i, j, k)[m]);
      space = H5Screate_simple(4, tdims, nullptr);
      ds = H5Dcreate2(grp, "turbulence", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
      H5Dclose(ds);
      H5Sclose(space);
    }
    H5Gclose(grp);
  }
  H5Gclose(blocks);
  if (H5Fclose(file) < 0) fail("error closing restart file '{}'", tmp);
  std::filesystem::rename(tmp, path);
}

RestartInfo read_restart(const std::string& path, const Grid& g, FlowField& f) {
  if (!std::filesystem::exists(path)) fail("restart file '{}' does not exist", path);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) fail("restart file '{}' is not a readable HDF5 file", path);
  RestartInfo info;
  info.iteration = read_scalar_attr<int>(file, "iteration", H5T_NATIVE_INT, path);
  info.reference_norm = read_scalar_attr<double>(file, "reference_norm", H5T_NATIVE_DOUBLE, path);
  info.wall_seconds = read_scalar_attr<double>(file, "wall_seconds", H5T_NATIVE_DOUBLE, path);
  if (H5Aexists(file, "body_force") > 0)
    info.body_force = read_scalar_attr<double>(file, "body_force", H5T_NATIVE_DOUBLE, path);
  if (H5Aexists(file, "turbulence_reference_0") > 0) {
    info.turbulence_reference[0] = read_scalar_attr<double>(file, "turbulence_reference_0", H5T_NATIVE_DOUBLE, path);
    info.turbulence_reference[1] = read_scalar_attr<double>(file, "turbulence_reference_1", H5T_NATIVE_DOUBLE, path);
  }
  std::vector<double> buf;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    const std::string name = "blocks/" + b.name + "/Q";
    if (H5Lexists(file, "blocks", H5P_DEFAULT) <= 0 ||
        H5Lexists(file, ("blocks/" + b.name).c_str(), H5P_DEFAULT) <= 0)
      fail("restart '{}' has no block '{}': it was written for another grid", path, b.name);
    hid_t ds = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    hid_t space = H5Dget_space(ds);
    hsize_t dims[4] = {0, 0, 0, 0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    if (dims[0] != static_cast<hsize_t>(b.nk) || dims[1] != static_cast<hsize_t>(b.nj) ||
        dims[2] != static_cast<hsize_t>(b.ni) || dims[3] != kNumEq)
      fail("restart '{}': block '{}' has {}x{}x{} cells, the grid {}x{}x{}", path, b.name, dims[2], dims[1], dims[0],
           b.ni, b.nj, b.nk);
    buf.resize(b.cells() * kNumEq);
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
    H5Sclose(space);
    H5Dclose(ds);
    std::size_t n = 0;
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i)
          for (int m = 0; m < kNumEq; ++m) f.Q[ib](i, j, k)[m] = buf[n++];
    const std::string tname = "blocks/" + b.name + "/turbulence";
    if (H5Lexists(file, tname.c_str(), H5P_DEFAULT) > 0) {
      if (f.turb.size() != g.blocks.size()) {
        f.turb.clear();
        for (const Block& bb : g.blocks) f.turb.emplace_back(bb.ni, bb.nj, bb.nk, kGhost, TurbState::Zero());
      }
      buf.resize(b.cells() * 2);
      ds = H5Dopen2(file, tname.c_str(), H5P_DEFAULT);
      H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
      H5Dclose(ds);
      n = 0;
      for (int k = 0; k < b.nk; ++k)
        for (int j = 0; j < b.nj; ++j)
          for (int i = 0; i < b.ni; ++i)
            for (int m = 0; m < 2; ++m) f.turb[ib](i, j, k)[m] = buf[n++];
    }
  }
  H5Fclose(file);
  return info;
}

}  // namespace narwhal
