// seam Python bindings: the extension module seam._seam (pybind11). The public API, with its
// argument conversion and option checks, is the package seam (python/seam/__init__.py); this
// module takes arrays already converted there (float64 / int64, shape (n, 3)) and checks them
// again, so that a direct call cannot crash it either.
//
// Arrays in: read in place by calls.cpp, which copies them into the library's types (the only
// copy), with the GIL released while the library runs. Arrays out: the library's vectors handed
// to NumPy (each owned by a capsule), no copy. Exceptions: seam::InvalidInput -> seam.InputError
// (also a ValueError), seam::IOError and seam::InternalError (and any other C++ exception) ->
// seam.InternalError (a RuntimeError), std::bad_alloc -> MemoryError; seam.Error is the base of
// seam's own.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "calls.h"

#include <seam/errors.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using seam_python::CheckOut;
using seam_python::Curve;
using seam_python::CurveView;
using seam_python::EmbedArgs;
using seam_python::EmbedOut;
using seam_python::Kernel;
using seam_python::MeshOut;
using seam_python::MeshView;
using seam_python::PairArgs;
using seam_python::PairOut;
using seam_python::Point;
using seam_python::TextileArgs;
using seam_python::TextileOut;

namespace {

// The exception classes, created once by the module (kept alive by it and by these references).
PyObject* error_class = nullptr;
PyObject* input_error_class = nullptr;
PyObject* internal_error_class = nullptr;

[[noreturn]] void input_error(const std::string& message) { throw seam::InvalidInput(message); }

/// `a` must be a C-contiguous array of T (native byte order) with shape (n, 3).
template <class T> void require_rows(const py::array& a, const char* dtype_name, const std::string& name) {
  if (!py::isinstance<py::array_t<T>>(a))  // the dtype, compared by NumPy (PyArray_EquivTypes)
    input_error(name + ": must be an array of dtype " + dtype_name + " (seam converts it; see help(seam))");
  if (a.ndim() != 2 || a.shape(1) != 3) {
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    input_error(name + ": must have shape (n, 3), got (" + shape + (a.ndim() == 1 ? ",)" : ")"));
  }
  if (!(a.flags() & py::array::c_style)) input_error(name + ": must be C-contiguous");
}

MeshView mesh_view(const py::array& V, const py::array& F, const std::string& v_name, const std::string& f_name) {
  require_rows<double>(V, "float64", v_name);
  require_rows<std::int64_t>(F, "int64", f_name);
  MeshView m;
  m.vertices = V.data();
  m.nv = static_cast<std::size_t>(V.shape(0));
  m.faces = F.data();
  m.nf = static_cast<std::size_t>(F.shape(0));
  m.vertices_name = v_name;
  m.faces_name = f_name;
  return m;
}

std::vector<CurveView> curve_views(const std::vector<py::array>& curves) {
  std::vector<CurveView> views;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    require_rows<double>(curves[i], "float64", "curves[" + std::to_string(i) + "]");
    views.push_back({curves[i].data(), static_cast<std::size_t>(curves[i].shape(0))});
  }
  return views;
}

/// A NumPy array of T with shape `shape` over the elements of `v` (each Elem is one or more T:
/// a Point is three doubles), which the array takes over (a capsule owns it): no copy.
template <class T, class Elem> py::array_t<T> take(std::vector<Elem>&& v, std::vector<py::ssize_t> shape) {
  static_assert(sizeof(Elem) % sizeof(T) == 0, "an element is whole values");
  if (v.empty()) return py::array_t<T>(shape);
  auto* owned = new std::vector<Elem>(std::move(v));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<Elem>*>(p); });
  return py::array_t<T>(shape, reinterpret_cast<const T*>(owned->data()), owner);
}

py::array_t<double> points_array(std::vector<Point>&& points) {
  const auto n = static_cast<py::ssize_t>(points.size());
  return take<double>(std::move(points), {n, 3});
}

py::list curves_list(std::vector<Curve>&& curves) {
  py::list list;
  for (auto& c : curves) list.append(points_array(std::move(c)));
  return list;
}

py::dict mesh_dict(MeshOut&& m) {
  py::dict d;
  const auto nf = static_cast<py::ssize_t>(m.faces.size());
  d["V"] = points_array(std::move(m.vertices));
  d["F"] = take<std::int64_t>(std::move(m.faces), {nf, 3});
  if (!m.source_face.empty() || nf == 0) {
    d["source_face"] = take<std::int64_t>(std::move(m.source_face), {nf});
    static_assert(sizeof(bool) == sizeof(std::uint8_t), "NumPy's bool is one byte, 0 or 1");
    d["new_face"] = take<bool>(std::move(m.new_face), {nf});
  }
  return d;
}

py::dict py_pair(const py::array& VA, const py::array& FA, const py::array& VB, const py::array& FB,
                 const std::string& kernel, double snap_tol, double min_angle, double max_area, long bound_reach,
                 bool improve, const std::optional<std::vector<py::array>>& curves) {
  const MeshView a = mesh_view(VA, FA, "VA", "FA"), b = mesh_view(VB, FB, "VB", "FB");
  PairArgs args;
  args.kernel.name = kernel;
  args.snap_tol = snap_tol;
  args.min_angle = min_angle;
  args.max_area = max_area;
  args.bound_reach = bound_reach;
  args.improve = improve;
  if (curves) {
    args.given_curves = true;
    args.curves = curve_views(*curves);
  }
  PairOut out;
  {
    py::gil_scoped_release release;
    out = seam_python::pair(a, b, args);
  }
  py::dict d;
  d["a"] = mesh_dict(std::move(out.a));
  d["b"] = mesh_dict(std::move(out.b));
  d["curves"] = curves_list(std::move(out.curves));
  d["report"] = py::bytes(out.report);
  return d;
}

py::dict py_embed(const py::array& V, const py::array& F, const std::vector<py::array>& curves, const std::string& kernel,
                  double snap_tol, double min_angle, double max_area, double max_distance, double curve_tol) {
  const MeshView m = mesh_view(V, F, "V", "F");
  const std::vector<CurveView> views = curve_views(curves);
  EmbedArgs args;
  args.kernel.name = kernel;
  args.snap_tol = snap_tol;
  args.min_angle = min_angle;
  args.max_area = max_area;
  args.max_distance = max_distance;
  args.curve_tol = curve_tol;
  EmbedOut out;
  {
    py::gil_scoped_release release;
    out = seam_python::embed(m, views, args);
  }
  py::dict d = mesh_dict(std::move(out.mesh));
  d["curves"] = curves_list(std::move(out.curves));
  py::list ids;
  for (auto& c : out.curve_vertices) {
    const auto n = static_cast<py::ssize_t>(c.size());
    ids.append(take<std::int64_t>(std::move(c), {n}));
  }
  d["curve_vertices"] = ids;
  d["report"] = py::bytes(out.report);
  return d;
}

py::dict py_check(const py::array& VA, const py::array& FA, const py::array& VB, const py::array& FB, const py::array& VA2,
                  const py::array& FA2, const py::array& VB2, const py::array& FB2, const std::vector<py::array>& curves,
                  double tol, const std::string& kernel) {
  const MeshView a = mesh_view(VA, FA, "VA", "FA"), b = mesh_view(VB, FB, "VB", "FB");
  const MeshView a2 = mesh_view(VA2, FA2, "VA2", "FA2"), b2 = mesh_view(VB2, FB2, "VB2", "FB2");
  const std::vector<CurveView> views = curve_views(curves);
  CheckOut out;
  {
    py::gil_scoped_release release;
    out = seam_python::check(a, b, a2, b2, views, tol, Kernel{kernel});
  }
  py::dict d;
  d["ok"] = out.ok;
  d["problems"] = out.problems;
  d["report"] = py::bytes(out.report);
  return d;
}

py::dict py_textile(const std::vector<std::pair<py::array, py::array>>& tows, const std::vector<std::string>& names,
                    const std::string& kernel, double snap_tol, double min_angle, double max_area, long bound_reach,
                    bool improve, int threads) {
  std::vector<MeshView> views;
  for (std::size_t i = 0; i < tows.size(); ++i) {
    const std::string name = "tows[" + std::to_string(i) + "]";
    views.push_back(mesh_view(tows[i].first, tows[i].second, name + ".V", name + ".F"));
  }
  TextileArgs args;
  args.kernel.name = kernel;
  args.snap_tol = snap_tol;
  args.min_angle = min_angle;
  args.max_area = max_area;
  args.bound_reach = bound_reach;
  args.improve = improve;
  args.threads = threads;
  TextileOut out;
  {
    py::gil_scoped_release release;
    out = seam_python::textile(views, names, args);
  }
  py::list tow_list, pair_list;
  for (auto& t : out.tows) tow_list.append(mesh_dict(std::move(t)));
  for (auto& p : out.pairs) {
    py::dict d;
    d["a"] = p.a;
    d["b"] = p.b;
    d["curves"] = curves_list(std::move(p.curves));
    pair_list.append(d);
  }
  py::dict d;
  d["tows"] = tow_list;
  d["pairs"] = pair_list;
  d["report"] = py::bytes(out.report);
  return d;
}

py::tuple py_make_crossover(int weft_along, int weft_around, int warp_along, int warp_around, const std::string& warp_section,
                            double warp_height) {
  std::array<MeshOut, 2> tows;
  {
    py::gil_scoped_release release;
    tows = seam_python::make_crossover(weft_along, weft_around, warp_along, warp_around, warp_section, warp_height);
  }
  py::tuple result(2);
  for (std::size_t i = 0; i < 2; ++i) {
    const py::dict d = mesh_dict(std::move(tows[i]));
    result[i] = py::make_tuple(d["V"], d["F"]);
  }
  return result;
}

}  // namespace

PYBIND11_MODULE(_seam, m) {
  m.doc() = "seam's compiled core; use the package seam (help(seam)).";

  error_class = PyErr_NewExceptionWithDoc("seam.Error", "Base of the exceptions seam raises.", PyExc_Exception, nullptr);
  const py::tuple input_bases = py::make_tuple(py::handle(error_class), py::handle(PyExc_ValueError));
  input_error_class = PyErr_NewExceptionWithDoc(
      "seam.InputError", "Bad input: an array of the wrong shape or type, a non-finite coordinate, an index out of range, "
      "a mesh that is not a valid 2-manifold triangle mesh, an option out of range. The message names the array or option.",
      input_bases.ptr(), nullptr);
  const py::tuple internal_bases = py::make_tuple(py::handle(error_class), py::handle(PyExc_RuntimeError));
  internal_error_class = PyErr_NewExceptionWithDoc(
      "seam.InternalError", "seam could not produce a valid result from valid input (the CLI's exit code 3).",
      internal_bases.ptr(), nullptr);
  if (!error_class || !input_error_class || !internal_error_class) throw py::error_already_set();
  m.add_object("Error", py::handle(error_class).inc_ref());
  m.add_object("InputError", py::handle(input_error_class).inc_ref());
  m.add_object("InternalError", py::handle(internal_error_class).inc_ref());

  // One translator, tried before pybind11's own (which gets what is rethrown here).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const seam::InvalidInput& e) {
      PyErr_SetString(input_error_class, e.what());
    } catch (const seam::Error& e) {  // InternalError; IOError (no file is read or written here)
      PyErr_SetString(internal_error_class, e.what());
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const py::error_already_set&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;  // MemoryError
    } catch (const std::exception& e) {
      PyErr_SetString(internal_error_class, e.what());
    }
  });

  using namespace pybind11::literals;
  m.def("pair", &py_pair, "VA"_a, "FA"_a, "VB"_a, "FB"_a, "kernel"_a, "snap_tol"_a, "min_angle"_a, "max_area"_a,
        "bound_reach"_a, "improve"_a, "curves"_a);
  m.def("embed", &py_embed, "V"_a, "F"_a, "curves"_a, "kernel"_a, "snap_tol"_a, "min_angle"_a, "max_area"_a,
        "max_distance"_a, "curve_tol"_a);
  m.def("check", &py_check, "VA"_a, "FA"_a, "VB"_a, "FB"_a, "VA2"_a, "FA2"_a, "VB2"_a, "FB2"_a, "curves"_a, "tol"_a,
        "kernel"_a);
  m.def("textile", &py_textile, "tows"_a, "names"_a, "kernel"_a, "snap_tol"_a, "min_angle"_a, "max_area"_a,
        "bound_reach"_a, "improve"_a, "threads"_a);
  m.def("make_crossover", &py_make_crossover, "weft_along"_a, "weft_around"_a, "warp_along"_a, "warp_around"_a,
        "warp_section"_a, "warp_height"_a);
}
