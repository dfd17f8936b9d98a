#pragma once
// Owning 3-D array with `ng` ghost layers on every side, indexed (i,j,k) with
// i in [-ng, ni+ng) etc. (AMReX Array4 style: negative ghost indices are valid).
// i runs fastest in memory, matching the lexicographic SGS sweep order.
#include <cassert>
#include <vector>

#include "core/types.hpp"

namespace narwhal {

template <class T>
class GhostArray {
 public:
  GhostArray() = default;
  GhostArray(int ni, int nj, int nk, int ng, const T& init = T{}) { resize(ni, nj, nk, ng, init); }

  void resize(int ni, int nj, int nk, int ng, const T& init = T{}) {
    ni_ = ni;
    nj_ = nj;
    nk_ = nk;
    ng_ = ng;
    sj_ = ni + 2 * ng;
    sk_ = static_cast<std::ptrdiff_t>(sj_) * (nj + 2 * ng);
    data_.assign(static_cast<std::size_t>(sk_) * (nk + 2 * ng), init);
  }

  T& operator()(int i, int j, int k) { return data_[offset(i, j, k)]; }
  const T& operator()(int i, int j, int k) const { return data_[offset(i, j, k)]; }
  T& operator()(const Index3& c) { return (*this)(c[0], c[1], c[2]); }
  const T& operator()(const Index3& c) const { return (*this)(c[0], c[1], c[2]); }

  bool contains(int i, int j, int k) const {
    return i >= -ng_ && i < ni_ + ng_ && j >= -ng_ && j < nj_ + ng_ && k >= -ng_ && k < nk_ + ng_;
  }
  void fill(const T& v) { std::fill(data_.begin(), data_.end(), v); }

  int ni() const { return ni_; }
  int nj() const { return nj_; }
  int nk() const { return nk_; }
  int ng() const { return ng_; }
  int extent(int d) const { return d == 0 ? ni_ : (d == 1 ? nj_ : nk_); }
  std::vector<T>& raw() { return data_; }
  const std::vector<T>& raw() const { return data_; }

 private:
  std::size_t offset(int i, int j, int k) const {
    assert(contains(i, j, k));
    return static_cast<std::size_t>((k + ng_) * sk_ + static_cast<std::ptrdiff_t>(j + ng_) * sj_ + (i + ng_));
  }
  std::vector<T> data_;
  int ni_ = 0, nj_ = 0, nk_ = 0, ng_ = 0;
  int sj_ = 0;
  std::ptrdiff_t sk_ = 0;
};

}  // namespace narwhal
