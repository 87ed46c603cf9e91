// seam: the three CGAL kernels every algorithm is compiled for.
//
//   Exact    (CGAL::Epeck)  exact predicates and exact constructions (lazy GMP rationals).
//                           Every constructed point (crossing point, Steiner point) is exact.
//   Filtered (CGAL::Epick)  exact predicates on double coordinates, rounded constructions.
//   Float    (CGAL::Simple_cartesian<double>)  nothing exact: plain double arithmetic.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>

#include <string>
#include <type_traits>

namespace seam {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using Filtered = CGAL::Exact_predicates_inexact_constructions_kernel;
using Float = CGAL::Simple_cartesian<double>;

enum class KernelKind { exact, filtered, float_ };

/// "exact", "filtered" or "float".
inline const char* kernel_name(KernelKind k) {
  switch (k) {
    case KernelKind::exact: return "exact";
    case KernelKind::filtered: return "filtered";
    case KernelKind::float_: return "float";
  }
  return "?";
}

template <class K> struct kernel_traits;
template <> struct kernel_traits<Exact> {
  static constexpr KernelKind kind = KernelKind::exact;
  static constexpr bool exact_constructions = true;
};
template <> struct kernel_traits<Filtered> {
  static constexpr KernelKind kind = KernelKind::filtered;
  static constexpr bool exact_constructions = false;
};
template <> struct kernel_traits<Float> {
  static constexpr KernelKind kind = KernelKind::float_;
  static constexpr bool exact_constructions = false;
};

/// Calls f(K{}) with the kernel named by `kind`; in a generic lambda, `using K = decltype(k);`.
template <class F> decltype(auto) with_kernel(KernelKind kind, F&& f) {
  switch (kind) {
    case KernelKind::filtered: return f(Filtered{});
    case KernelKind::float_: return f(Float{});
    case KernelKind::exact: break;
  }
  return f(Exact{});
}

/// A point of any kernel rounded to double coordinates, as a Filtered point (for the AABB trees
/// and k-d trees, which search on doubles). Exact for points that came from doubles.
template <class P> Filtered::Point_3 to_filtered(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    // From the interval approximation: p.x() would build a lazy number for each coordinate.
    const auto& q = CGAL::approx(p);
    return Filtered::Point_3(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
  } else {
    return Filtered::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
}

/// For kernels with lazy exact numbers: replace the expression tree behind `x` by its exact
/// value, so that kept points do not pin ever-growing trees. A no-op for the other kernels.
template <class T> inline void make_exact(T& x) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<T>::Kernel, Exact>) CGAL::exact(x);
}

/// Whether every coordinate of `p` is a double exactly, known from its approximation alone: under
/// the exact kernel an interval approximation that is a point holds the exact value, which is
/// then that double (a wider interval says nothing: false). True for the other kernels, whose
/// coordinates are doubles.
template <class P> inline bool is_double_by_approximation(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    const auto& q = CGAL::approx(p);
    return q.x().inf() == q.x().sup() && q.y().inf() == q.y().sup() && q.z().inf() == q.z().sup();
  } else {
    return true;
  }
}

/// Under the exact kernel: makes `p` exact unless its interval approximation is a point (a
/// double already). Its rounding (to_filtered: the middle of the approximation) is then a function
/// of its value alone, not of which computations happened to refine it first. A no-op for the
/// other kernels. (A const point may be given: evaluating it changes only its representation,
/// shared by every copy, which CGAL keeps mutable.)
template <class P> inline void fix_rounding(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    if (!is_double_by_approximation(p)) CGAL::exact(p);
  }
}

}  // namespace seam
