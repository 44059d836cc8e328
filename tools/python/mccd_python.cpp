// The compiled part of the Python module `mccd` (mccd._mccd): the Scene and its queries over
// NumPy arrays, mesh files, the built-in scenes, and the engine of `mccd run`.
//
// Arrays in (positions):  read in place when they are float64 or float32 in native byte order,
//   aligned, with strides that are positive multiples of the item size (C order, Fortran order,
//   and slices such as X[:, :3]); anything else (other dtypes, negative or odd strides, lists)
//   is converted once to a C-ordered float64 array. Either way the call holds a reference to
//   every array it reads until it returns, so nothing can be freed under a running step.
// Arrays out: contacts, the frames of a built-in scene and the meshes read from files are
//   NumPy arrays over the C++ vectors themselves (moved into the array's owner, not copied).
// Errors: every mccd::Error becomes mccd.Error (a ValueError) with the same message; this file
//   raises mccd.Error too, in the same words, for what only Python can get wrong (a dtype, a
//   shape, a type), always before any state changes.
// Threads: every step, query, scene build, file read and run releases the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <bit>
#include <cctype>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <mutex>
#include <ctime>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <mccd/geometry/error.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/mesh_io.h>
#include <mccd/parallel/scene.h>

#include "fixtures/scenes.h"
#include "options.h"
#include "run_driver.h"
#include "run_input.h"
#include "run_table.h"

#ifndef MCCD_VERSION
#define MCCD_VERSION "unknown"
#endif

namespace py = pybind11;
using namespace pybind11::literals;

namespace mccd::python {

namespace {

// ---------------------------------------------------------------------------------------------
// Arrays in

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// "shape (10, 4) of float64": how an array's message describes it.
std::string describe(const py::array& a) { return "shape " + shape_text(a) + " of " + py::str(a.dtype()).cast<std::string>(); }

/// `obj` as an ndarray (numpy.asarray for lists and other array-likes), or mccd::Error.
py::array as_array(py::handle obj, const std::string& what) {
  if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
  try {
    return py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw Error(what + ": cannot be read as an array (" + std::string(e.what()) + ")");
  }
}

bool is_real(const py::array& a) {
  const char k = a.dtype().kind();
  return k == 'f' || k == 'i' || k == 'u';
}

bool native_order(const py::dtype& d) {
  const char b = d.byteorder();
  constexpr char native = std::endian::native == std::endian::little ? '<' : '>';
  return b == '=' || b == '|' || b == native;
}

template <class T>
PositionsView strided_view(const void* data, py::ssize_t rows, py::ssize_t cols, py::ssize_t row_stride,
                           py::ssize_t col_stride) {
  using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Strides = Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>;
  const Eigen::Map<const Matrix, Eigen::Unaligned, Strides> map(static_cast<const T*>(data), rows, cols,
                                                                 Strides(row_stride, col_stride));
  return PositionsView(map);
}

/// A view of `obj`'s positions for a step: in place when the memory allows (see the top of this
/// file), else over a float64 copy. `keep` receives the array read, to hold while the step runs;
/// `pointer` the address the view reads (0 for none). None is an empty view (a static mesh).
/// The row and column counts are left for the step to check, in its own words.
PositionsView positions_view(py::handle obj, const std::string& what, std::vector<py::object>& keep,
                             std::uintptr_t& pointer) {
  pointer = 0;
  if (obj.is_none()) return {};
  py::array a = as_array(obj, what);
  if (a.ndim() != 2 || !is_real(a))
    throw Error(what + ": expected an n x 3 array of float64 or float32 coordinates, got " + describe(a));
  const py::ssize_t rows = a.shape(0), cols = a.shape(1);
  py::ssize_t item = a.itemsize(), rs = a.strides(0), cs = a.strides(1);
  if (rows <= 1) rs = cols * item;  // the stride of a dimension of length 0 or 1 is arbitrary
  if (cols <= 1) cs = item;
  const int num = a.dtype().num();
  const bool in_place = (num == py::detail::npy_api::NPY_DOUBLE_ || num == py::detail::npy_api::NPY_FLOAT_) &&
                        native_order(a.dtype()) && rs > 0 && cs > 0 && rs % item == 0 && cs % item == 0 &&
                        reinterpret_cast<std::uintptr_t>(a.data()) % static_cast<std::uintptr_t>(item) == 0;
  if (!in_place) {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!a) throw Error(what + ": cannot be converted to float64 (" + describe(py::reinterpret_borrow<py::array>(obj)) + ")");
    item = sizeof(double), rs = cols * item, cs = item;
  }
  keep.push_back(a);
  pointer = reinterpret_cast<std::uintptr_t>(a.data());
  if (item == sizeof(double)) return strided_view<double>(a.data(), rows, cols, rs / item, cs / item);
  return strided_view<float>(a.data(), rows, cols, rs / item, cs / item);
}

/// "a list of n x 3 arrays, one per mesh", or one array for a scene of one mesh.
std::vector<py::handle> per_mesh_items(py::handle arg, std::size_t meshes, const std::string& which) {
  std::vector<py::handle> items;
  if (py::isinstance<py::array>(arg)) {
    items.push_back(arg);
  } else if (py::isinstance<py::list>(arg) || py::isinstance<py::tuple>(arg)) {
    for (py::handle h : py::reinterpret_borrow<py::sequence>(arg)) items.push_back(h);
  } else {
    throw Error(which + ": expected a list of n x 3 arrays, one per mesh (or one array for a scene of one mesh), got " +
                std::string(py::str(py::type::handle_of(arg).attr("__name__"))));
  }
  if (items.size() != meshes)  // the words of Scene::step's own check
    throw Error(which + ": " + std::to_string(items.size()) + " position arrays for " + std::to_string(meshes) +
                " meshes");
  return items;
}

/// A mesh from (V, F) or (V, F, name): copied into the scene's own arrays.
TriMesh mesh_from(py::handle item, std::size_t index) {
  TriMesh mesh;
  mesh.name = "mesh " + std::to_string(index);
  if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) || py::isinstance<py::array>(item))
    throw Error(mesh.name + ": expected a (V, F) or (V, F, name) tuple, got " +
                std::string(py::str(py::type::handle_of(item).attr("__name__"))));
  const auto parts = py::reinterpret_borrow<py::sequence>(item);
  if (parts.size() != 2 && parts.size() != 3)
    throw Error(mesh.name + ": expected a (V, F) or (V, F, name) tuple, got " + std::to_string(parts.size()) + " items");
  if (parts.size() == 3) {
    if (!py::isinstance<py::str>(parts[2]))
      throw Error(mesh.name + ": the name (third item) must be a str");
    mesh.name = parts[2].cast<std::string>();
  }
  // V: any real dtype and layout, copied as float64.
  {
    const std::string what = mesh.name + ": V";
    std::vector<py::object> keep;
    std::uintptr_t pointer = 0;
    const py::object v = parts[0];
    if (v.is_none()) throw Error(what + ": expected an n x 3 array of coordinates, got None");
    const PositionsView view = positions_view(v, what, keep, pointer);
    if (view.cols() != 3)
      throw Error(what + ": expected an n x 3 array of coordinates, got " + describe(py::array(keep.front())));
    mesh.vertices.resize(view.rows());
    for (std::size_t i = 0; i < view.rows(); ++i)
      for (int k = 0; k < 3; ++k) mesh.vertices(i, k) = view(i, k);
  }
  // F: any integer dtype, each index in [0, 2^32) here and below the vertex count in the scene.
  {
    const std::string what = mesh.name + ": F";
    const py::array f = as_array(parts[1], what);
    const char kind = f.dtype().kind();
    if (f.ndim() != 2 || f.shape(1) != 3 || (kind != 'i' && kind != 'u'))
      throw Error(what + ": expected an m x 3 integer array of vertex indices, got " + describe(f));
    const std::size_t m = static_cast<std::size_t>(f.shape(0)), nv = mesh.num_vertices();
    mesh.faces.resize(m);
    auto out_of_range = [&](std::size_t face, const std::string& value) {
      return Error(mesh.name + ": face " + std::to_string(face) + ": vertex index " + value + " out of range [0, " +
                   std::to_string(nv) + ")");
    };
    if (kind == 'i') {
      const auto c = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(f);
      const std::int64_t* p = c.data();
      for (std::size_t i = 0; i < 3 * m; ++i) {
        if (p[i] < 0 || p[i] > std::int64_t(UINT32_MAX)) throw out_of_range(i / 3, std::to_string(p[i]));
        mesh.faces[i / 3][i % 3] = static_cast<std::uint32_t>(p[i]);
      }
    } else {
      const auto c = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(f);
      const std::uint64_t* p = c.data();
      for (std::size_t i = 0; i < 3 * m; ++i) {
        if (p[i] > UINT32_MAX) throw out_of_range(i / 3, std::to_string(p[i]));
        mesh.faces[i / 3][i % 3] = static_cast<std::uint32_t>(p[i]);
      }
    }
  }
  return mesh;
}

/// A bool, or one bool per mesh (Python or NumPy bools only: 0 and 1 could be mesh indices).
std::vector<bool> per_mesh_flags(py::handle value, const char* name, std::size_t meshes, bool fallback) {
  const py::object np_bool = py::module_::import("numpy").attr("bool_");
  auto is_bool = [&](py::handle h) { return PyBool_Check(h.ptr()) || py::isinstance(h, np_bool); };
  if (value.is_none()) return std::vector<bool>(meshes, fallback);
  if (is_bool(value)) return std::vector<bool>(meshes, value.cast<bool>());
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value))
    throw Error(std::string(name) + ": expected a bool or one bool per mesh");
  const auto seq = py::reinterpret_borrow<py::sequence>(value);
  if (seq.size() != meshes)
    throw Error(std::string(name) + ": " + std::to_string(seq.size()) + " values for " + std::to_string(meshes) +
                " meshes");
  std::vector<bool> out;
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!is_bool(seq[m]))
      throw Error(std::string(name) + ": mesh " + std::to_string(m) + ": expected a bool, got " +
                  std::string(py::str(py::type::handle_of(seq[m]).attr("__name__"))));
    out.push_back(seq[m].cast<bool>());
  }
  return out;
}

int checked_threads(int threads) {
  if (threads < 1 || threads > cli::kMaxThreads)
    throw Error("threads: " + std::to_string(threads) + ": expected 1 to " + std::to_string(cli::kMaxThreads) +
                " (or None)");
  return threads;
}

// ---------------------------------------------------------------------------------------------
// Arrays out

/// A NumPy array over `v`'s own memory: `v` is moved into the array's owner (no copy).
template <class T>
py::array owning_array(std::vector<T>&& v, const py::dtype& dtype, std::vector<py::ssize_t> shape,
                       std::vector<py::ssize_t> strides) {
  auto* held = new std::vector<T>(std::move(v));
  py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array(dtype, std::move(shape), std::move(strides), held->data(), owner);
}

py::array positions_array(Positions&& p) {
  const auto n = static_cast<py::ssize_t>(p.rows());
  return owning_array(std::move(p.xyz()), py::dtype::of<double>(), {n, 3}, {3 * py::ssize_t(sizeof(double)), sizeof(double)});
}

py::array faces_array(std::vector<Triangle>&& faces) {
  static_assert(sizeof(Triangle) == 3 * sizeof(std::uint32_t));
  const auto m = static_cast<py::ssize_t>(faces.size());
  return owning_array(std::move(faces), py::dtype::of<std::uint32_t>(), {m, 3},
                      {py::ssize_t(sizeof(Triangle)), sizeof(std::uint32_t)});
}

/// The structured dtype over mccd::Contact itself: kind, mesh_a, a, mesh_b, b, vertices (4),
/// toi. `vertices` spans a_vertices and b_vertices, which the binding fills for vertex-face
/// contacts too (the vertex, then the face's three), as `mccd run` writes them.
const py::dtype& contact_dtype() {
  static_assert(offsetof(Contact, b_vertices) == offsetof(Contact, a_vertices) + 2 * sizeof(std::uint32_t));
  static_assert(sizeof(ContactKind) == 1);
  static const py::dtype* dtype = new py::dtype(py::dtype::from_args(py::dict(
      "names"_a = py::make_tuple("kind", "mesh_a", "a", "mesh_b", "b", "vertices", "toi"),
      "formats"_a = py::make_tuple("u1", "u4", "u4", "u4", "u4", py::make_tuple("u4", py::make_tuple(4)), "f8"),
      "offsets"_a = py::make_tuple(offsetof(Contact, kind), offsetof(Contact, mesh_a), offsetof(Contact, a),
                                   offsetof(Contact, mesh_b), offsetof(Contact, b), offsetof(Contact, a_vertices),
                                   offsetof(Contact, toi)),
      "itemsize"_a = sizeof(Contact))));  // never freed: it outlives the interpreter's last use
  return *dtype;
}

/// Fills the vertex ids of vertex-face contacts: the vertex, then the face's three.
void fill_face_vertices(const Scene& scene, std::vector<Contact>& contacts) {
  for (Contact& c : contacts) {
    if (c.kind != ContactKind::VertexFace) continue;
    const Triangle& f = scene.mesh(c.mesh_b).faces[c.b];
    c.a_vertices = {c.a, f[0]};
    c.b_vertices = {f[1], f[2]};
  }
}

py::array contacts_array(std::vector<Contact>&& contacts) {
  const auto n = static_cast<py::ssize_t>(contacts.size());
  return owning_array(std::move(contacts), contact_dtype(), {n}, {py::ssize_t(sizeof(Contact))});
}

py::dict counters_dict(const CcdCounters& c) {
  return py::dict("queries"_a = c.queries, "box_culled"_a = c.box_culled, "coplanar_culled"_a = c.coplanar_culled,
                  "root_tests"_a = c.root_tests, "fast_hits"_a = c.fast_hits, "fast_misses"_a = c.fast_misses,
                  "fallbacks"_a = c.fallbacks, "pieces"_a = c.pieces, "hits"_a = c.hits, "touches"_a = c.touches);
}

/// Every field of StepStats under its C++ name (CcdCounters and WorkSpan as nested dicts).
py::dict stats_dict(const StepStats& s) {
  py::dict d;
  d["method"] = to_string(s.method);
  d["updated_vertices"] = s.updated_vertices;
  d["refit_nodes"] = s.refit_nodes;
  d["volume_tests"] = s.volume_tests;
  d["triangle_tests"] = s.triangle_tests;
  d["feature_box_tests"] = s.feature_box_tests;
  d["vf_filtered"] = s.vf_filtered;
  d["ee_filtered"] = s.ee_filtered;
  d["vf_tests"] = s.vf_tests;
  d["ee_tests"] = s.ee_tests;
  d["vf_ccd"] = counters_dict(s.vf_ccd);
  d["ee_ccd"] = counters_dict(s.ee_ccd);
  d["vf_contacts"] = s.vf_contacts;
  d["ee_contacts"] = s.ee_contacts;
  d["leaf_pairs"] = s.leaf_pairs;
  d["adjacent_leaf_pairs"] = s.adjacent_leaf_pairs;
  d["repeated_leaf_pairs"] = s.repeated_leaf_pairs;
  d["culled_patches"] = s.culled_patches;
  d["culled_nodes"] = s.culled_nodes;
  d["sprouted"] = s.sprouted;
  d["invalidated"] = s.invalidated;
  d["rebuilds"] = s.rebuilds;
  d["orphan_vf_tested"] = s.orphan_vf_tested;
  d["orphan_ee_tested"] = s.orphan_ee_tested;
  d["front_size"] = s.front_size;
  d["front_bytes"] = s.front_bytes;
  d["t_update"] = s.t_update;
  d["t_refit"] = s.t_refit;
  d["t_front"] = s.t_front;
  d["t_self"] = s.t_self;
  d["t_contacts"] = s.t_contacts;
  d["t_total"] = s.t_total;
  const std::pair<const char*, const WorkSpan*> ws[] = {{"ws_update", &s.ws_update}, {"ws_refit", &s.ws_refit},
                                                        {"ws_search", &s.ws_search}, {"ws_self", &s.ws_self},
                                                        {"ws_branch", &s.ws_branch}, {"ws_join", &s.ws_join},
                                                        {"ws_input", &s.ws_input}};
  for (const auto& [name, w] : ws) d[name] = py::dict("work"_a = w->work, "span"_a = w->span);
  return d;
}

/// The calling thread's CPU time (time.thread_time() in Python), for the measurement.
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// ---------------------------------------------------------------------------------------------
// The scene

struct PyStepResult {
  py::array contacts;
  double earliest_toi;
  py::dict stats;
};

enum class Call { Step, Advance, CollisionFree, EarliestImpact, Candidates };

struct PyScene {
  std::unique_ptr<tbb::task_arena> arena;  // declared first: it outlives the scene using it
  std::unique_ptr<Scene> scene;
  std::optional<int> threads;
  /// Testing aids: the addresses the views of the last call read (start and end, per mesh),
  /// and a callable run with the GIL released before each step reads its views.
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> last_views;
  py::object step_hook = py::none();

  PyScene(const py::sequence& meshes, const std::string& method, std::optional<int> threads_, double min_distance,
          py::handle is_static, py::handle self_collision, const std::string& volume, const std::string& bvh,
          unsigned leaf_size, const std::string& representatives, bool self_culling, std::size_t max_front_bytes,
          bool work_span)
      : threads(threads_) {
    if (py::isinstance<py::str>(meshes) || py::isinstance<py::array>(meshes))
      throw Error("meshes: expected a list of (V, F) tuples");
    std::vector<TriMesh> ms;
    for (std::size_t m = 0; m < meshes.size(); ++m) ms.push_back(mesh_from(meshes[m], m));
    SceneOptions o;
    o.method = parse_method(method.c_str());
    o.volume = parse_volume(volume.c_str());
    o.bvh = parse_bvh_build(bvh.c_str());
    o.leaf_size = leaf_size;
    o.representatives = parse_representatives(representatives.c_str());
    o.min_distance = min_distance;
    o.self_culling = self_culling;
    o.max_front_bytes = max_front_bytes;
    o.work_span = work_span;
    const std::vector<bool> st = per_mesh_flags(is_static, "static", ms.size(), false);
    const std::vector<bool> sc = per_mesh_flags(self_collision, "self_collision", ms.size(), true);
    for (std::size_t m = 0; m < ms.size(); ++m) o.meshes.push_back({st[m], sc[m]});
    if (threads) arena = std::make_unique<tbb::task_arena>(checked_threads(*threads));
    o.arena = arena.get();
    py::gil_scoped_release release;
    scene = std::make_unique<Scene>(std::move(ms), o);
  }

  std::size_t num_meshes() const { return scene->num_meshes(); }

  std::vector<PositionsView> views(py::handle arg, const std::string& which, std::vector<py::object>& keep,
                                   std::vector<std::uintptr_t>& pointers) const {
    const std::vector<py::handle> items = per_mesh_items(arg, num_meshes(), which);
    std::vector<PositionsView> out;
    for (std::size_t m = 0; m < items.size(); ++m) {
      std::uintptr_t p = 0;
      out.push_back(positions_view(items[m], which + ", mesh " + std::to_string(m) + " (" + scene->mesh(m).name + ")",
                                   keep, p));
      pointers.push_back(p);
    }
    return out;
  }

  /// One call of the scene: the arrays read (in place or converted), the GIL released, the
  /// step or query run, the result turned into Python objects.
  py::object call(Call call, py::handle start, py::handle end, const std::optional<std::string>& method) {
    std::optional<Method> m;
    if (method) m = parse_method(method->c_str());
    const bool query = call != Call::Step && call != Call::Advance;
    std::vector<py::object> keep;  // every array read, held until the call returns
    std::vector<std::uintptr_t> ps, pe;
    std::vector<PositionsView> vs, ve;
    if (call == Call::Advance) {
      ve = views(end, "advance", keep, pe);
    } else {
      vs = views(start, query ? "query start" : "step start", keep, ps);
      ve = views(end, query ? "query end" : "step end", keep, pe);
    }
    last_views.clear();
    for (std::size_t i = 0; i < num_meshes(); ++i) last_views.emplace_back(ps.empty() ? 0 : ps[i], pe[i]);
    const py::object hook = step_hook;

    StepResult r;
    bool free = false;
    double earliest = 0;
    {
      py::gil_scoped_release release;
      if (!hook.is_none()) {
        py::gil_scoped_acquire acquire;
        hook();
      }
      switch (call) {
        case Call::Step: r = scene->step(vs, ve, m); break;
        case Call::Advance: r = scene->advance(ve, m); break;
        case Call::CollisionFree: free = scene->is_collision_free(vs, ve); break;
        case Call::EarliestImpact: earliest = scene->earliest_impact(vs, ve); break;
        case Call::Candidates: r.contacts = scene->candidates(vs, ve); break;
      }
      fill_face_vertices(*scene, r.contacts);
    }
    switch (call) {
      case Call::CollisionFree: return py::bool_(free);
      case Call::EarliestImpact: return py::float_(earliest);
      case Call::Candidates: return contacts_array(std::move(r.contacts));
      default: break;
    }
    PyStepResult out{contacts_array(std::move(r.contacts)), r.earliest_toi, stats_dict(r.stats)};
    return py::cast(std::move(out));
  }

  /// Testing aid: one step timed inside C++ (views made first, untimed; the result dropped
  /// inside the timing), the C++ side of the Python-versus-C++ measurement.
  py::tuple time_cpp_step(py::handle start, py::handle end) {
    std::vector<py::object> keep;
    std::vector<std::uintptr_t> ps, pe;
    const std::vector<PositionsView> vs = views(start, "step start", keep, ps), ve = views(end, "step end", keep, pe);
    double seconds = 0, cpu = 0;
    std::size_t contacts = 0;
    {
      py::gil_scoped_release release;
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = thread_cpu_seconds();
      {
        const StepResult r = scene->step(vs, ve);
        contacts = r.contacts.size();
      }
      cpu = thread_cpu_seconds() - c0;
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    return py::make_tuple(seconds, cpu, contacts);
  }
};

// ---------------------------------------------------------------------------------------------
// The run engine

struct PyRunResult {
  py::array steps;
  py::dict summary;
};

struct RunRecord {
  std::uint64_t step, vf, ee;
  double first_impact, seconds;
};

const py::dtype& run_dtype() {
  static const py::dtype* dtype = new py::dtype(py::dtype::from_args(py::dict(
      "names"_a = py::make_tuple("step", "vf", "ee", "first_impact", "seconds"),
      "formats"_a = py::make_tuple("u8", "u8", "u8", "f8", "f8"),
      "offsets"_a = py::make_tuple(offsetof(RunRecord, step), offsetof(RunRecord, vf), offsetof(RunRecord, ee),
                                   offsetof(RunRecord, first_impact), offsetof(RunRecord, seconds)),
      "itemsize"_a = sizeof(RunRecord))));
  return *dtype;
}

/// Thrown through the engine when Python asks to stop (Ctrl-C): the files are finished as
/// `partial` says, then the Python exception is raised.
struct PythonStop : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::vector<std::string> frame_arguments(py::handle frames) {
  const py::object fspath = py::module_::import("os").attr("fspath");
  std::vector<std::string> out;
  if (py::isinstance<py::str>(frames) || py::hasattr(frames, "__fspath__")) {
    out.push_back(fspath(frames).cast<std::string>());
  } else if (py::isinstance<py::sequence>(frames)) {
    for (py::handle f : py::reinterpret_borrow<py::sequence>(frames)) out.push_back(fspath(f).cast<std::string>());
  } else {
    throw Error("frames: expected a path, a printf pattern, a folder, or a list of paths");
  }
  return out;
}

void check_range(const char* name, long long v, long long lo, long long hi) {
  if (v < lo || v > hi)
    throw Error(std::string(name) + ": " + std::to_string(v) + ": expected " + std::to_string(lo) + " to " +
                std::to_string(hi));
}

PyRunResult run(py::object frames, std::optional<std::string> scene, int size, int frame_count,
                const std::string& method, std::optional<int> threads, int substeps, double min_distance,
                std::optional<py::object> contacts, std::optional<py::object> stats, const std::string& partial,
                std::optional<py::object> image, std::optional<std::size_t> image_step,
                std::pair<int, int> image_size, std::optional<std::string> camera, std::optional<py::object> colored,
                const std::string& volume, const std::string& bvh, unsigned leaf_size,
                const std::string& representatives, bool self_culling) {
  const py::object fspath = py::module_::import("os").attr("fspath");
  auto path = [&](const std::optional<py::object>& p) { return p && !p->is_none() ? fspath(*p).cast<std::string>() : ""; };
  if (scene && !frames.is_none()) throw Error("give either frames or scene=, not both");
  if (!scene && frames.is_none()) throw Error("no frames given (files, a pattern like frame%03d.ply, a folder, or scene=NAME)");
  cli::RunSettings st;
  st.scene.method = parse_method(method.c_str());
  st.scene.volume = parse_volume(volume.c_str());
  st.scene.bvh = parse_bvh_build(bvh.c_str());
  st.scene.leaf_size = leaf_size;
  st.scene.representatives = parse_representatives(representatives.c_str());
  st.scene.self_culling = self_culling;
  st.scene.min_distance = min_distance;
  validate(st.scene);
  check_range("substeps", substeps, 1, 1000);
  st.substeps = substeps;
  st.threads = threads ? checked_threads(*threads) : static_cast<int>(tbb::info::default_concurrency());
  st.contacts = path(contacts);
  st.stats = path(stats);
  if (partial != "keep" && partial != "remove") throw Error("partial: '" + partial + "': expected 'keep' or 'remove'");
  st.partial = partial == "remove" ? cli::Partial::Remove : cli::Partial::Keep;
  st.image = path(image);
  st.colored = path(colored);
  st.image_step = image_step;
  check_range("image_size width", image_size.first, 16, 4096);
  check_range("image_size height", image_size.second, 16, 4096);
  st.image_width = image_size.first, st.image_height = image_size.second;
  st.camera = camera.value_or("");
  st.silent = st.quiet = st.mute = true;
  st.exit_zero = true;

  // The run goes on a thread of its own while this one waits for it, looking for signals
  // (Python handles them on its main thread) every few milliseconds; a signal that raises
  // (Ctrl-C: KeyboardInterrupt) asks the run to stop at the end of its current step, whichever
  // thread ends it.
  std::vector<cli::StepRow> rows;
  std::atomic<bool> stop{false};
  std::string reason;  // the exception's name, written before `stop`
  st.on_step = [&](const cli::StepRow& row) {
    rows.push_back(row);
    if (stop.load(std::memory_order_acquire)) throw PythonStop(reason);
  };
  cli::RunInput input;
  std::vector<std::string> given;
  if (scene) {
    check_range("size", size, 1, 200);
    check_range("frame_count", frame_count, 2, 5000);
  } else {
    given = frame_arguments(frames);
  }
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      input = scene ? cli::input_from_scene(*scene, size, frame_count, st.threads) : cli::input_from_files(given);
      cli::run_frames(input, st, "mccd.run");
    } catch (...) {
      failure = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(mutex);
    done = true;
    finished.notify_all();
  });
  std::optional<py::error_already_set> pending;
  for (bool over = false; !over;) {
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(mutex);
      over = finished.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; });
    }
    if (!over && !pending && PyErr_CheckSignals() != 0) {
      pending.emplace();  // the handler's exception, raised once the run has stopped
      reason = py::str(pending->type().attr("__name__")).cast<std::string>();
      stop.store(true, std::memory_order_release);
    }
  }
  worker.join();
  if (pending) throw *pending;
  if (failure) std::rethrow_exception(failure);

  std::vector<RunRecord> records;
  cli::RunTotals totals;
  for (const cli::StepRow& r : rows) {
    records.push_back({r.step, r.vf, r.ee, r.first, r.stats.t_total});
    totals.add(r);
  }
  const auto n = static_cast<py::ssize_t>(records.size());
  const bool any = totals.vf + totals.ee > 0;
  py::dict summary("steps"_a = totals.steps, "steps_with_contacts"_a = totals.steps_with_contacts,
                   "vf_contacts"_a = totals.vf, "ee_contacts"_a = totals.ee,
                   "first_impact"_a = any ? py::object(py::float_(totals.first)) : py::object(py::none()),
                   "first_impact_step"_a = any ? py::object(py::int_(totals.first_step)) : py::object(py::none()),
                   "step_seconds"_a = totals.step_seconds, "input"_a = input.description);
  return {owning_array(std::move(records), run_dtype(), {n}, {py::ssize_t(sizeof(RunRecord))}), summary};
}

// ---------------------------------------------------------------------------------------------
// Docstrings

constexpr const char* kModuleDoc = R"(Continuous collision detection between deforming triangle meshes (the C++ library mccd).

Every vertex moves on a straight line over a time step; a step reports every vertex-face and
edge-edge pair that touches during it, each with a conservative time of impact in [0, 1].

    import mccd
    V0, F = mccd.load_mesh("cloth_ball92.ply")
    V1, _ = mccd.load_mesh("cloth_ball93.ply")
    scene = mccd.Scene([(V0, F)])
    r = scene.step([V0], [V1])
    print(len(r.contacts), r.earliest_toi, r.contacts[:5])

What is copied: Scene() copies the meshes (V and F) into the scene. step(), advance() and the
queries read float64 and float32 position arrays in place (C order, Fortran order, or any
positive strides that are multiples of the item size), and convert anything else once to a
C-ordered float64 array; either way the call holds every array it reads until it returns.
Results (contacts, load_mesh's arrays, make_scene's frames) are arrays over the C++ results'
own memory, not copies.

Threads: every step releases the GIL and runs on oneTBB, in the caller's arena or in one of
`threads` threads. One scene steps one call at a time: a second concurrent call raises.
Errors: every refusal raises mccd.Error (a ValueError) naming the mesh, the array and what is
wrong, before any state changes.)";

constexpr const char* kSceneDoc = R"(A scene of triangle meshes, stepped over time.

Scene(meshes, *, method="fbd", threads=None, min_distance=0.0, static=None,
      self_collision=None, volume="kdop18", bvh="sah", leaf_size=0,
      representatives="default", self_culling=True, max_front_bytes=0, work_span=False)

meshes: a list of (V, F) or (V, F, name) tuples. V: n x 3 coordinates (float64 or float32, or
    any real dtype, converted); F: m x 3 vertex indices (any integer dtype). Both are copied
    into the scene, which keeps V as the initial positions (the start of the first advance()).
    The name (default "mesh i") is used in error messages.
method: how a step finds its candidates: "fbd" (the default: the BVTT front tracked from step
    to step), "phc", "traverse" or "bruteforce"; all four report identical contacts.
threads: None runs every step in the calling thread's oneTBB arena (all cores by default);
    an int runs them in an arena of that many threads, owned by the scene.
min_distance: also report pairs that come within this distance (>= 0).
static: a bool, or one bool per mesh: a static mesh keeps its initial positions (pass None
    or its unchanged positions in a step), is never tested against itself nor against
    another static mesh.
self_collision: a bool, or one bool per mesh: whether a mesh's own triangles are tested
    against each other (default True; off for rigid bodies).
volume, bvh, leaf_size, representatives, self_culling, max_front_bytes, work_span: as
    SceneOptions in C++ (core/options.h); none of them changes the contacts (work_span fills
    the stats' ws_* entries: each stage's work and span).

Raises mccd.Error for a bad mesh (shape, dtype, an index out of range, a repeated index in a
face, a non-finite coordinate) or option.)";

constexpr const char* kInitDoc = R"(__init__(meshes, *, method="fbd", threads=None, min_distance=0.0, static=None, self_collision=None, volume="kdop18", bvh="sah", leaf_size=0, representatives="default", self_culling=True, max_front_bytes=0, work_span=False)

Builds the scene (its BVH and connectivity) from copies of the meshes; see help(mccd.Scene).)";

#define MCCD_POSITIONS_DOC                                                                   \
  "start, end: one n x 3 array per mesh (a list or tuple), or one array for a scene of\n"   \
  "    one mesh; None for a static mesh. float64 and float32 arrays are read in place (C\n" \
  "    order, Fortran order, or positive strides that are multiples of the item size);\n"  \
  "    other dtypes, other strides and lists are converted once to float64. Each array\n"   \
  "    read is held until the call returns.\n"

constexpr const char* kStepDoc =
    "step(start, end, *, method=None) -> StepResult\n\n"
    "One step: every vertex moves linearly from start to end. Returns a StepResult (the\n"
    "contacts, the earliest time of impact, the statistics); end becomes the start of the\n"
    "next advance(). The GIL is released while the step runs.\n\n" MCCD_POSITIONS_DOC
    "method: this step's method (default: the scene's).\n\n"
    "Raises mccd.Error, before any state changes, for a wrong count of arrays, a wrong\n"
    "shape or dtype, a non-finite coordinate, or a step of this scene already running in\n"
    "another thread.";

constexpr const char* kAdvanceDoc =
    "advance(next, *, method=None) -> StepResult\n\n"
    "One step from the last end positions (initially the meshes' own V) to next: one array\n"
    "per mesh (or one array for a scene of one mesh), read as step() reads end. Raises as\n"
    "step() does; after an error the last end positions are unchanged.";

constexpr const char* kCollisionFreeDoc =
    "is_collision_free(start, end) -> bool\n\n"
    "Whether no feature pair touches during the step from start to end (IPC Toolkit's\n"
    "is_step_collision_free). Stops at the first certified contact: much cheaper than step()\n"
    "when there is a contact. Leaves the scene as it was (advance() still starts from the\n"
    "last step's end).\n\n" MCCD_POSITIONS_DOC;

constexpr const char* kEarliestDoc =
    "earliest_impact(start, end) -> float\n\n"
    "The earliest conservative time of impact in [0, 1] of the step from start to end, inf\n"
    "when it is collision free; equal to step(start, end).earliest_toi, found with less\n"
    "work. For a line search: the motion is collision free up to that fraction of the step\n"
    "(IPC Toolkit's compute_collision_free_stepsize). Leaves the scene as it was.\n\n" MCCD_POSITIONS_DOC;

constexpr const char* kCandidatesDoc =
    "candidates(start, end) -> numpy.ndarray\n\n"
    "The broad phase's feature pairs, untested, for hosts with their own narrow phase: each\n"
    "pair the elementary tests would see, as a record of mccd.CONTACT_DTYPE whose toi is a\n"
    "lower bound of any contact time (0, 0.25, 0.5 or 0.75: the start of the first quarter\n"
    "of the step in which the pair's swept volumes overlap). Leaves the scene as it was.\n\n" MCCD_POSITIONS_DOC;

constexpr const char* kMeshDoc =
    "mesh(i) -> (V, F, name)\n\n"
    "Mesh i as the scene holds it: its initial positions (n x 3 float64) and faces (m x 3\n"
    "uint32) as read-only views of the scene's own arrays (no copy; they keep the scene\n"
    "alive), and its name.";

constexpr const char* kLoadMeshDoc =
    "load_mesh(path) -> (V, F)\n\n"
    "Reads an OBJ or PLY file (by extension): V, n x 3 float64, and F, m x 3 uint32. The\n"
    "arrays own the memory the reader filled (no copy). Raises mccd.Error naming the file\n"
    "and the line or element that cannot be read.";

constexpr const char* kSaveMeshDoc =
    "save_mesh(path, V, F)\n\n"
    "Writes a mesh as binary little-endian PLY or as OBJ (by extension), with full double\n"
    "precision, through a temporary renamed at the end (a failed write leaves no file). V\n"
    "and F are read (and checked) as Scene() reads a mesh.";

constexpr const char* kMakeSceneDoc =
    "make_scene(name, size=4, frames=31) -> (meshes, frames)\n\n"
    "A built-in animated scene, the one `mccd run --scene NAME --size SIZE --frames FRAMES`\n"
    "steps: \"cloth\" (a cloth folding through itself), \"spheres\" (deforming spheres\n"
    "drifting into each other), \"random\" (random triangles), \"tube\" (a twisting tube) or\n"
    "\"drape\" (a cloth dropped onto a ball), of about `size` thousand triangles.\n"
    "meshes: a list of (V, F, name) for Scene(); frames: one list of position arrays (one per\n"
    "mesh) per frame, frames[0] the meshes' V. size times frames may be at most 20,000.";

constexpr const char* kRunDoc = R"(run(frames=None, *, scene=None, size=4, frame_count=31, method="fbd", threads=None, substeps=1, min_distance=0.0, contacts=None, stats=None, partial="keep", image=None, image_step=None, image_size=(1200, 900), camera=None, colored=None, volume="kdop18", bvh="sah", leaf_size=0, representatives="default", self_culling=True) -> RunResult

The work of the command `mccd run`, from Python: steps frame k -> k + 1 for every k of a
sequence (the next frame read while a step runs) and returns one record per step
(RunResult), writing the same files as the command.

frames: the frame files in order (a list of paths), one printf pattern
    ("frame%03d.ply"), or one folder (its .ply and .obj files in natural order); or
scene, size, frame_count: a built-in scene instead (see make_scene()).
method, min_distance, volume, bvh, leaf_size, representatives, self_culling: as Scene().
threads: the size of the run's arena (default: every core).
substeps: linear sub-steps per frame interval (times of impact stay in frame time).
contacts: a .csv or .json file of every contact (frame, substep, kind, mesh_a,
    feature_a, mesh_b, feature_b, v0..v3, toi in frame time, t); stats: a .json file of
    every sub-step's statistics. Both are streamed as steps finish and renamed at the end;
    when the run stops early (a frame that cannot be read, Ctrl-C) they keep the finished
    steps, marked incomplete, or with partial="remove" are not written.
image, image_step, image_size, camera, colored: the picture (PNG) and the coloured PLY of
    the first contact (or of step image_step), as the command's --image options.

Raises mccd.Error for refused input (after finishing the files as partial says), and
KeyboardInterrupt on Ctrl-C, at the end of the step under way (from the main thread).)";

// ---------------------------------------------------------------------------------------------

}  // namespace

}  // namespace mccd::python

PYBIND11_MODULE(_mccd, m) {
  using namespace mccd;
  using namespace mccd::python;
  // Every docstring starts with its own signature, in Python's words (pybind11's would name
  // handle and object where the call takes arrays).
  py::options options;
  options.disable_function_signatures();
  m.doc() = kModuleDoc;
  m.attr("__version__") = MCCD_VERSION;

  py::register_exception<Error>(m, "Error", PyExc_ValueError);
  m.attr("Error").attr("__doc__") =
      "Raised for every refused input (a mesh, an array, an option, a file), with the library's message naming the "
      "mesh, the array or file and what is wrong. Nothing has changed when it is raised. A subclass of ValueError.";

  m.attr("VERTEX_FACE") = static_cast<int>(ContactKind::VertexFace);
  m.attr("EDGE_EDGE") = static_cast<int>(ContactKind::EdgeEdge);
  m.attr("CONTACT_DTYPE") = contact_dtype();
  m.attr("RUN_STEP_DTYPE") = run_dtype();
  m.attr("simd_level") = detail::to_string(detail::lane_kernels().level);  // as `mccd --version`

  py::class_<PyStepResult>(m, "StepResult", R"(What a step found.

contacts: a NumPy structured array (dtype mccd.CONTACT_DTYPE), one record per feature pair that
    touches during the step, in the canonical order (kind, then (mesh_a, a), then (mesh_b, b)):
    kind (mccd.VERTEX_FACE = 0: a is a vertex of mesh_a, b a face of mesh_b; mccd.EDGE_EDGE = 1:
    a and b are edges), mesh_a, a, mesh_b, b, vertices (4 vertex ids: the vertex then the
    face's three, or the two vertices of each edge) and toi (a conservative time of impact in
    [0, 1], never later than the true one). The array owns the C++ result's memory (no copy).
earliest_toi: the earliest toi (inf when there is no contact).
stats: a dict of what the step did (test counts, front size, stage times t_* in seconds).)")
      .def_readonly("contacts", &PyStepResult::contacts, "the contacts (dtype mccd.CONTACT_DTYPE)")
      .def_readonly("earliest_toi", &PyStepResult::earliest_toi, "the earliest time of impact (inf when none)")
      .def_readonly("stats", &PyStepResult::stats, "what the step did: counts and stage times")
      .def("__len__", [](const PyStepResult& r) { return r.contacts.shape(0); }, "__len__() -> int: the number of contacts")
      .def("__repr__", [](const PyStepResult& r) {
        const auto c = r.contacts;
        std::size_t vf = 0;
        const auto* p = static_cast<const Contact*>(c.data());
        for (py::ssize_t i = 0; i < c.shape(0); ++i) vf += p[i].kind == ContactKind::VertexFace;
        return "<mccd.StepResult: " + std::to_string(c.shape(0)) + " contacts (" + std::to_string(vf) +
               " vertex-face, " + std::to_string(c.shape(0) - py::ssize_t(vf)) + " edge-edge), earliest_toi " +
               py::str(py::float_(r.earliest_toi)).cast<std::string>() + ">";
      });

  py::class_<PyScene>(m, "Scene", kSceneDoc)
      .def(py::init<const py::sequence&, const std::string&, std::optional<int>, double, py::handle, py::handle,
                    const std::string&, const std::string&, unsigned, const std::string&, bool, std::size_t, bool>(),
           "meshes"_a, py::kw_only(), "method"_a = "fbd", "threads"_a = py::none(), "min_distance"_a = 0.0,
           "static"_a = py::none(), "self_collision"_a = py::none(), "volume"_a = "kdop18", "bvh"_a = "sah",
           "leaf_size"_a = 0u, "representatives"_a = "default", "self_culling"_a = true, "max_front_bytes"_a = 0u,
           "work_span"_a = false, kInitDoc)
      .def(
          "step",
          [](PyScene& s, py::handle start, py::handle end, std::optional<std::string> method) {
            return s.call(Call::Step, start, end, method);
          },
          "start"_a, "end"_a, py::kw_only(), "method"_a = py::none(), kStepDoc)
      .def(
          "advance",
          [](PyScene& s, py::handle next, std::optional<std::string> method) {
            return s.call(Call::Advance, py::none(), next, method);
          },
          "next"_a, py::kw_only(), "method"_a = py::none(), kAdvanceDoc)
      .def(
          "is_collision_free",
          [](PyScene& s, py::handle start, py::handle end) {
            return s.call(Call::CollisionFree, start, end, std::nullopt).cast<bool>();
          },
          "start"_a, "end"_a, kCollisionFreeDoc)
      .def(
          "earliest_impact",
          [](PyScene& s, py::handle start, py::handle end) {
            return s.call(Call::EarliestImpact, start, end, std::nullopt).cast<double>();
          },
          "start"_a, "end"_a, kEarliestDoc)
      .def(
          "candidates",
          [](PyScene& s, py::handle start, py::handle end) {
            return s.call(Call::Candidates, start, end, std::nullopt);
          },
          "start"_a, "end"_a, kCandidatesDoc)
      .def(
          "mesh",
          [](py::object self, std::size_t i) {
            const PyScene& s = self.cast<const PyScene&>();
            if (i >= s.num_meshes())
              throw Error("mesh " + std::to_string(i) + ": the scene has " + std::to_string(s.num_meshes()) + " meshes");
            const TriMesh& mesh = s.scene->mesh(i);
            py::array v(py::dtype::of<double>(), {py::ssize_t(mesh.num_vertices()), py::ssize_t(3)},
                        {3 * py::ssize_t(sizeof(double)), py::ssize_t(sizeof(double))}, mesh.vertices.data(), self);
            py::array f(py::dtype::of<std::uint32_t>(), {py::ssize_t(mesh.num_faces()), py::ssize_t(3)},
                        {py::ssize_t(sizeof(Triangle)), py::ssize_t(sizeof(std::uint32_t))}, mesh.faces.data(), self);
            v.attr("flags").attr("writeable") = false;
            f.attr("flags").attr("writeable") = false;
            return py::make_tuple(v, f, mesh.name);
          },
          "i"_a, kMeshDoc)
      .def_property_readonly("num_meshes", &PyScene::num_meshes, "the number of meshes")
      .def_property_readonly(
          "threads", [](const PyScene& s) { return s.threads; },
          "the size of the scene's own arena, or None (steps run in the calling thread's arena)")
      .def_property_readonly(
          "method", [](const PyScene& s) { return to_string(s.scene->options().method); },
          "the default method of step() and advance()")
      .def_property_readonly(
          "bvh_depth", [](const PyScene& s) { return s.scene->bvh_depth(); }, "the depth of the scene's BVH")
      .def("__repr__",
           [](const PyScene& s) {
             std::size_t nv = 0, nf = 0;
             for (std::size_t i = 0; i < s.num_meshes(); ++i)
               nv += s.scene->mesh(i).num_vertices(), nf += s.scene->mesh(i).num_faces();
             return "<mccd.Scene: " + std::to_string(s.num_meshes()) + " mesh" + (s.num_meshes() == 1 ? "" : "es") +
                    ", " + std::to_string(nv) + " vertices, " + std::to_string(nf) + " triangles, method " +
                    to_string(s.scene->options().method) + ", threads " +
                    (s.threads ? std::to_string(*s.threads) : std::string("None")) + ">";
           })
      .def(
          "_last_view_data", [](const PyScene& s) { return s.last_views; },
          "_last_view_data() -> [(start, end), ...]\n\n"
          "Testing aid: the data addresses the last call's views read, one (start, end) pair\n"
          "per mesh (0: no array). An argument read in place gives its own address.")
      .def(
          "_set_step_hook", [](PyScene& s, py::object hook) { s.step_hook = std::move(hook); }, "hook"_a,
          "_set_step_hook(hook)\n\n"
          "Testing aid: a callable run (holding the GIL) after a step or query has released the\n"
          "GIL and before it reads its arrays; None removes it.")
      .def("_time_cpp_step", &PyScene::time_cpp_step, "start"_a, "end"_a,
           "_time_cpp_step(start, end) -> (seconds, thread_cpu_seconds, contacts)\n\n"
           "Testing aid: one step(start, end) timed inside C++ (the views made before the clock\n"
           "starts, the result destroyed before it stops): wall time and the calling thread's\n"
           "CPU time. The C++ side of the measurement of tools/python/bench/bench_step.py.");

  m.def(
      "load_mesh",
      [](py::object path) {
        const std::string p = py::module_::import("os").attr("fspath")(path).cast<std::string>();
        TriMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = read_mesh(p);
        }
        return py::make_tuple(positions_array(std::move(mesh.vertices)), faces_array(std::move(mesh.faces)));
      },
      "path"_a, kLoadMeshDoc);

  m.def(
      "save_mesh",
      [](py::object path, py::handle V, py::handle F) {
        const std::string p = py::module_::import("os").attr("fspath")(path).cast<std::string>();
        const TriMesh mesh = mesh_from(py::make_tuple(V, F, p), 0);
        std::string ext = p.size() >= 4 ? p.substr(p.size() - 4) : "";
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".ply" && ext != ".obj") throw Error(p + ": expected a .ply or .obj file name");
        py::gil_scoped_release release;
        validate_mesh(mesh);
        if (ext == ".ply")
          write_ply(p, mesh);
        else
          write_obj(p, mesh);
      },
      "path"_a, "V"_a, "F"_a, kSaveMeshDoc);

  m.def(
      "make_scene",
      [](const std::string& name, int size, int frames) {
        check_range("size", size, 1, 200);
        check_range("frames", frames, 2, 5000);
        cli::check_scene_size(size, frames);
        AnimatedScene scene;
        {
          py::gil_scoped_release release;
          scene = make_scene(name, size, frames);
        }
        py::list meshes, seq;
        for (TriMesh& mesh : scene.meshes)
          meshes.append(py::make_tuple(positions_array(std::move(mesh.vertices)), faces_array(std::move(mesh.faces)),
                                       mesh.name));
        for (auto& frame : scene.frames) {
          py::list f;
          for (Positions& p : frame) f.append(positions_array(std::move(p)));
          seq.append(f);
        }
        return py::make_tuple(meshes, seq);
      },
      "name"_a, "size"_a = 4, "frames"_a = 31, kMakeSceneDoc);

  py::class_<PyRunResult>(m, "RunResult", R"(What mccd.run() found.

steps: a NumPy structured array (dtype mccd.RUN_STEP_DTYPE), one record per step (frame k to
    k + 1, its sub-steps together): step, vf and ee (pairs in contact during the step, each
    pair once), first_impact (in frame time, k + t; inf when none) and seconds (the step's
    computation time).
summary: a dict: steps, steps_with_contacts, vf_contacts, ee_contacts (summed over the
    steps), first_impact and first_impact_step (None when there is no contact),
    step_seconds, input (what was run).)")
      .def_readonly("steps", &PyRunResult::steps, "one record per step (dtype mccd.RUN_STEP_DTYPE)")
      .def_readonly("summary", &PyRunResult::summary, "the totals over the run")
      .def("__len__", [](const PyRunResult& r) { return r.steps.shape(0); }, "__len__() -> int: the number of steps")
      .def("__repr__", [](const PyRunResult& r) {
        return "<mccd.RunResult: " + std::string(py::str(static_cast<const py::object&>(r.summary))) + ">";
      });

  m.def("run", &run, "frames"_a = py::none(), py::kw_only(), "scene"_a = py::none(), "size"_a = 4,
        "frame_count"_a = 31, "method"_a = "fbd", "threads"_a = py::none(), "substeps"_a = 1, "min_distance"_a = 0.0,
        "contacts"_a = py::none(), "stats"_a = py::none(), "partial"_a = "keep", "image"_a = py::none(),
        "image_step"_a = py::none(), "image_size"_a = std::make_pair(1200, 900), "camera"_a = py::none(),
        "colored"_a = py::none(), "volume"_a = "kdop18", "bvh"_a = "sah", "leaf_size"_a = 0u,
        "representatives"_a = "default", "self_culling"_a = true, kRunDoc);
}
