// The Python module `tumble` (pybind11): the C++ API's World and BatchWorld, with the batch's
// arrays handed to numpy as views, without copies. docs/python.md describes it.
//
// Errors: tumble::SceneError becomes tumble.SceneError (a ValueError), tumble::Error becomes
// tumble.Error (a RuntimeError); an array of the wrong shape or dtype, or with a NaN, is a
// ValueError naming what was expected; an index out of range is an IndexError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "collision/sdf/sdf_tree.hpp"
#include "scenes/neural_sdf_file.hpp"
#include "scenes/scene_loader.hpp"
#include "scenes/sdf_section.hpp"
#include "tumble/tumble.hpp"

namespace py = pybind11;

namespace {

using tumble::BatchWorld;
using tumble::BodyId;
using tumble::Real;
using tumble::Vec3;

Vec3 vec3(const std::vector<Real>& v, const char* what) {
  if (v.size() != 3)
    throw py::value_error(std::string(what) + ": expected 3 numbers, got " +
                          std::to_string(v.size()));
  return Vec3(v[0], v[1], v[2]);
}

tumble::Quat quat(const std::vector<Real>& q) {
  if (q.size() != 4)
    throw py::value_error("orientation: expected 4 numbers (w, x, y, z), got " +
                          std::to_string(q.size()));
  return tumble::Quat(q[0], q[1], q[2], q[3]);
}

// Sets the Python error `type` with `what`. A message may quote a file name that is not UTF-8 (its
// bytes as the system has them): such bytes are shown as \xNN rather than lost (a str made as
// UTF-8 from them would be empty).
void raise_with_message(PyObject* type, const char* what) {
  PyObject* text = PyUnicode_DecodeUTF8(what, py::ssize_t(std::strlen(what)), "backslashreplace");
  if (text == nullptr)
    return;  // the decoding's own error stays set
  PyErr_SetObject(type, text);
  Py_DECREF(text);
}

// YAML text from a str as it is, or from a dict or list through JSON (a subset of YAML).
std::string yaml_of(const py::object& description, const char* what) {
  if (py::isinstance<py::str>(description)) {
    try {
      return description.cast<std::string>();
    } catch (const py::cast_error&) {
      throw py::value_error(std::string(what) +
                            ": the text cannot be written in UTF-8 (it holds a lone surrogate)");
    }
  }
  if (py::isinstance<py::dict>(description) || py::isinstance<py::list>(description))
    try {
      return py::module_::import("json").attr("dumps")(description).cast<std::string>();
    } catch (py::error_already_set& e) {
      if (e.matches(PyExc_RecursionError))
        throw py::value_error(std::string(what) + ": nested too deeply");
      throw;
    }
  throw py::type_error(std::string(what) + ": expected a dict (or YAML text) describing it");
}

// A pose from 3 numbers (a position) or 7 (position, then orientation w x y z: a
// trajectory.csv row's order).
tumble::Transform pose_of(const py::object& pose, const char* what) {
  std::vector<Real> v;
  try {
    v = pose.cast<std::vector<Real>>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(what) + ": expected a sequence of 3 or 7 numbers, got " +
                         std::string(py::str(py::type::of(pose).attr("__name__"))));
  }
  if (v.size() != 3 && v.size() != 7)
    throw py::value_error(std::string(what) +
                          ": expected 3 numbers (x, y, z) or 7 (x, y, z, qw, qx, qy, qz), got " +
                          std::to_string(v.size()));
  for (const Real x : v)
    if (!std::isfinite(x))
      throw py::value_error(std::string(what) + ": every number must be finite");
  tumble::Transform t;
  t.translation = Vec3(v[0], v[1], v[2]);
  if (v.size() == 7) {
    const tumble::Quat q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1) > 1e-6)
      throw py::value_error(std::string(what) + ": the orientation must be a unit quaternion");
    t.rotation = q.normalized();
  }
  return t;
}

py::array_t<Real> array_of(const Eigen::Ref<const Eigen::Matrix<Real, Eigen::Dynamic, 1>>& v) {
  py::array_t<Real> out(static_cast<py::ssize_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    out.mutable_at(i) = v[i];
  return out;
}

// The signed distance and gradient of `field` at points (3,) or (N, 3): a float and (3,), or
// (N,) and (N, 3).
template <class Field>
py::tuple sample_field(const Field& field, const py::object& points_object) {
  const py::array_t<Real, py::array::c_style | py::array::forcecast> points(points_object);
  const bool one = points.ndim() == 1;
  if (!((one && points.shape(0) == 3) || (points.ndim() == 2 && points.shape(1) == 3)))
    throw py::value_error("points: expected shape (3,) or (N, 3)");
  const py::ssize_t n = one ? 1 : points.shape(0);
  py::array_t<Real> distance(n);
  py::array_t<Real> gradient({n, py::ssize_t(3)});
  const Real* p = points.data();
  Real* d = distance.mutable_data();
  Real* g = gradient.mutable_data();
  for (py::ssize_t i = 0; i < n; ++i) {
    const Vec3 x(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    if (!x.allFinite())
      throw py::value_error("points: every coordinate must be finite");
    const tumble::sdf::Sample s = field.sample(x);
    d[i] = s.distance;
    for (int k = 0; k < 3; ++k)
      g[3 * i + k] = s.gradient[k];
  }
  if (one)
    return py::make_tuple(d[0], gradient.attr("reshape")(3));
  return py::make_tuple(distance, gradient);
}

// A file name as the system has it: a str (a name that was not UTF-8 comes back from os.fsencode
// as the bytes it was), bytes, or a path-like object such as pathlib.Path.
bool is_path(const py::object& path) {
  return py::isinstance<py::str>(path) || py::isinstance<py::bytes>(path) ||
         py::hasattr(path, "__fspath__");
}

std::string path_of(const py::object& path, const char* what) {
  if (!is_path(path))
    throw py::type_error(std::string(what) + ": expected a path (str, bytes or os.PathLike)");
  return py::module_::import("os").attr("fsencode")(path).cast<std::string>();
}

std::shared_ptr<const tumble::Scene> scene_from(const py::object& scene) {
  if (is_path(scene))
    return tumble::load_scene(path_of(scene, "scene"));
  try {
    // pybind11 casts None to an empty pointer: refused like any other non-scene.
    if (std::shared_ptr<const tumble::Scene> loaded =
            scene.cast<std::shared_ptr<const tumble::Scene>>())
      return loaded;
  } catch (const py::cast_error&) {
  }
  throw py::type_error("scene: expected a path (str, bytes or os.PathLike) or a tumble.Scene");
}

// A numpy view of `data` (shape `shape`), kept alive by `owner`.
template <class T>
py::array_t<T> view(T* data, std::vector<py::ssize_t> shape, py::handle owner, bool writable) {
  py::array_t<T> a(shape, data, owner);
  if (!writable)
    a.attr("setflags")(py::arg("write") = false);
  return a;
}

// Copies `values` into `out` after checking its shape against [worlds][bodies][width] and that
// every number is finite.
void copy_checked(const py::object& given, std::span<Real> out, int worlds, int bodies, int width,
                  const char* what) {
  // Lists and other array-likes are taken through numpy, as numpy itself would.
  const py::array values = py::module_::import("numpy").attr("asarray")(given);
  if (!py::isinstance<py::array_t<double>>(values) || values.dtype().kind() != 'f' ||
      values.itemsize() != sizeof(double))
    throw py::value_error(std::string(what) + ": expected a float64 array of shape (" +
                          std::to_string(worlds) + ", " + std::to_string(bodies) + ", " +
                          std::to_string(width) + "), got dtype " +
                          py::str(values.dtype()).cast<std::string>());
  const bool shape_ok = values.ndim() == 3 && values.shape(0) == worlds &&
                        values.shape(1) == bodies && values.shape(2) == width;
  if (!shape_ok) {
    std::string got = "(";
    for (py::ssize_t d = 0; d < values.ndim(); ++d)
      got += (d > 0 ? ", " : "") + std::to_string(values.shape(d));
    got += values.ndim() == 1 ? ",)" : ")";
    throw py::value_error(std::string(what) + ": expected shape (" + std::to_string(worlds) + ", " +
                          std::to_string(bodies) + ", " + std::to_string(width) + "), got " + got);
  }
  const auto typed = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  const double* in = typed.data();
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(in[i])) {
      const std::size_t per_world = std::size_t(bodies) * std::size_t(width);
      throw py::value_error(std::string(what) + "[" + std::to_string(i / per_world) + ", " +
                            std::to_string(i % per_world / std::size_t(width)) + ", " +
                            std::to_string(i % std::size_t(width)) + "] is " +
                            std::to_string(in[i]) + ", not a finite number");
    }
  }
  std::copy(in, in + out.size(), out.begin());
}

// A Python or numpy integer (anything with __index__, but not bool) as a C++ integer of the
// given range, or TypeError / `out_of_range`'s error naming `what`.
py::int_ exact_integer(const py::handle h, const std::string& what) {
  if (py::isinstance<py::bool_>(h))
    throw py::type_error(what + " must be integers, got a bool");
  try {
    return py::module_::import("operator").attr("index")(h);
  } catch (const py::error_already_set&) {
    throw py::type_error(what + " must be integers, got " + py::repr(h).cast<std::string>());
  }
}

std::vector<int> world_ids(const py::object& ids, int worlds) {
  std::vector<int> list;
  for (const py::handle h : ids) {
    const py::int_ value = exact_integer(h, "reset: world ids");
    const std::string text = py::repr(value).cast<std::string>();
    long long id = -1;
    try {
      id = value.cast<long long>();
    } catch (const py::cast_error&) {
      throw py::index_error("reset: world " + text + " out of range for a batch of " +
                            std::to_string(worlds));
    }
    if (id < 0 || id >= worlds)
      throw py::index_error("reset: world " + text + " out of range for a batch of " +
                            std::to_string(worlds));
    list.push_back(static_cast<int>(id));
  }
  return list;
}

// A seed: a whole number from 0 to 2^64 - 1.
std::uint64_t seed_value(const py::handle h, const std::string& what) {
  const py::int_ value = exact_integer(h, what);
  const py::object zero = py::int_(0), limit = py::int_(std::uint64_t(-1));
  if (value < zero || value > limit)
    throw py::value_error(what + ": " + py::repr(value).cast<std::string>() +
                          " is not a seed from 0 to 2**64 - 1");
  return value.cast<std::uint64_t>();
}

std::vector<std::uint64_t> seed_list(const py::object& seeds) {
  std::vector<std::uint64_t> list;
  for (const py::handle h : seeds)
    list.push_back(seed_value(h, "reset: seeds"));
  return list;
}

int checked_world(const BatchWorld& batch, int index) {
  if (index < 0 || index >= batch.size())
    throw py::index_error("world " + std::to_string(index) + " out of range for a batch of " +
                          std::to_string(batch.size()));
  return index;
}

}  // namespace

PYBIND11_MODULE(_tumble, m) {
  m.doc() = "tumble: rigid-body physics centred on collision detection (docs/python.md)";
  m.attr("__version__") = tumble::kVersion;

  static py::exception<tumble::Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<tumble::SceneError> scene_error(m, "SceneError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p)
        std::rethrow_exception(p);
    } catch (const tumble::SceneError& e) {
      raise_with_message(scene_error.ptr(), e.what());
    } catch (const tumble::Error& e) {
      raise_with_message(error.ptr(), e.what());
    }
  });

  py::class_<tumble::Scene, std::shared_ptr<tumble::Scene>>(m, "Scene")
      .def_property_readonly("body_count", [](const tumble::Scene& s) { return s.bodies.size(); })
      .def_property_readonly("dt", [](const tumble::Scene& s) { return s.world.dt; })
      .def_property_readonly("body_names", [](const tumble::Scene& s) {
        std::vector<std::string> names;
        for (const tumble::BodyDesc& b : s.bodies)
          names.push_back(b.name);
        return names;
      });
  m.def(
      "load_scene",
      [](const py::object& path, bool allow_outside_files) {
        return std::const_pointer_cast<tumble::Scene>(tumble::load_scene(
            path_of(path, "path"), {.allow_outside_files = allow_outside_files}));
      },
      py::arg("path"), py::kw_only(), py::arg("allow_outside_files") = false,
      "Loads and checks a YAML scene; raises tumble.SceneError. The files it names must lie in "
      "its folder or below unless allow_outside_files.");
  m.def(
      "load_scene_text",
      [](const std::string& yaml, const std::string& name, bool allow_outside_files) {
        return std::const_pointer_cast<tumble::Scene>(
            tumble::load_scene_text(yaml, name, {.allow_outside_files = allow_outside_files}));
      },
      py::arg("yaml"), py::arg("name") = "<text>", py::kw_only(),
      py::arg("allow_outside_files") = false,
      "A scene from YAML text; the files it names must lie in the current folder or below unless "
      "allow_outside_files.");

  m.def(
      "randomized",
      [](const py::object& scene, const py::object& seed) {
        return std::make_shared<tumble::Scene>(
            tumble::randomized(*scene_from(scene), seed_value(seed, "seed")));
      },
      py::arg("scene"), py::arg("seed"),
      "The scene with the draws of its randomize block for `seed` (what a BatchWorld world with "
      "that seed steps); a World of it is that world.");

  m.def(
      "distance",
      [](const py::object& shape_a, const py::object& pose_a, const py::object& shape_b,
         const py::object& pose_b) {
        // Shapes as in a scene; a hull or compound is placed as the scene loader places it, so
        // that its points are where they were written when the pose is the identity.
        const auto shape_pose = [](const py::object& shape, const py::object& pose,
                                   const char* what, const char* pose_what) {
          Vec3 centre = Vec3::Zero();
          // A shape given in code, not a document from elsewhere: its files may lie anywhere.
          tumble::Shape s = tumble::load_shape_text(yaml_of(shape, what), what, &centre,
                                                    {.allow_outside_files = true});
          tumble::Transform t = pose_of(pose, pose_what);
          const Vec3 offset = t.rotation * centre;
          t.translation += offset;
          return std::make_tuple(s, t, offset);
        };
        const auto [a, ta, offset_a] = shape_pose(shape_a, pose_a, "shape_a", "pose_a");
        const auto [b, tb, offset_b] = shape_pose(shape_b, pose_b, "shape_b", "pose_b");
        tumble::ShapeDistance d = tumble::distance_between(a, ta, b, tb);
        // The library turns a body about its centre of mass; the pose given here is that of the
        // frame the shape was written in, `offset` from it. Turning about the frame's origin
        // also carries the centre around it: w x offset, at the rate of the translation gradient.
        d.gradient_a.tail<3>() += offset_a.cross(Vec3(d.gradient_a.head<3>()));
        d.gradient_b.tail<3>() += offset_b.cross(Vec3(d.gradient_b.head<3>()));
        py::dict out;
        out["distance"] = d.distance;
        out["point_a"] = array_of(d.point_a);
        out["point_b"] = array_of(d.point_b);
        out["normal"] = array_of(d.normal);
        out["gradient_a"] = array_of(d.gradient_a);
        out["gradient_b"] = array_of(d.gradient_b);
        out["converged"] = d.converged;
        return out;
      },
      py::arg("shape_a"), py::arg("pose_a"), py::arg("shape_b"), py::arg("pose_b"),
      "Signed distance of two convex shapes, a convex shape and a plane, or an SDF shape "
      "({'type': 'sdf', 'sdf': {...}}) and a convex shape, a plane or another SDF shape, "
      "written as in a scene ({'type': 'box', "
      "'half_extents': [1, 1, 1]}), at poses of 3 numbers (position) or "
      "7 (position, then w x y z): a dict with distance (negative in penetration), point_a, "
      "point_b, normal (from B to A), gradient_a and gradient_b (d distance / d pose: "
      "translation, then rotation about the pose's position, world axes) and converged.");

  m.def(
      "contact_potential",
      [](const py::dict& distance, Real stiffness, Real max_gradient) {
        // The dict tumble.distance returns: its distance and the two gradients of 6.
        const auto number = [&](const char* key) {
          if (!distance.contains(key))
            throw py::value_error(std::string("contact_potential: distance has no '") + key +
                                  "' (pass what tumble.distance returns)");
          return distance[key];
        };
        // A value of the wrong type is a ValueError too, not pybind11's cast error.
        const auto as = [](const py::object& value, const char* key, auto* type) {
          using T = std::remove_pointer_t<decltype(type)>;
          try {
            return value.cast<T>();
          } catch (const py::cast_error&) {
            throw py::value_error(
                std::string("contact_potential: ") + key +
                (std::is_same_v<T, Real> ? " must be a number" : " must be 6 numbers"));
          }
        };
        const auto gradient = [&](const char* key) {
          const std::vector<Real> v =
              as(number(key), key, static_cast<std::vector<Real>*>(nullptr));
          if (v.size() != 6)
            throw py::value_error(std::string("contact_potential: ") + key +
                                  " must have 6 numbers, got " + std::to_string(v.size()));
          tumble::PoseGradient g;
          for (int k = 0; k < 6; ++k) {
            if (!std::isfinite(v[std::size_t(k)]))
              throw py::value_error(std::string("contact_potential: ") + key + " must be finite");
            g[k] = v[std::size_t(k)];
          }
          return g;
        };
        if (!(std::isfinite(stiffness) && stiffness >= 0))
          throw py::value_error("contact_potential: stiffness must be finite and not negative");
        if (!(max_gradient > 0))
          throw py::value_error("contact_potential: max_gradient must be positive");
        tumble::ShapeDistance d;
        d.distance = as(number("distance"), "distance", static_cast<Real*>(nullptr));
        if (!std::isfinite(d.distance))
          throw py::value_error("contact_potential: the distance must be finite");
        d.gradient_a = gradient("gradient_a");
        d.gradient_b = gradient("gradient_b");
        const tumble::ContactPotential p = tumble::contact_potential(d, stiffness, max_gradient);
        py::dict out;
        out["value"] = p.value;
        out["gradient_a"] = array_of(p.gradient_a);
        out["gradient_b"] = array_of(p.gradient_b);
        return out;
      },
      py::arg("distance"), py::arg("stiffness"), py::arg("max_gradient"),
      "The smooth contact potential of a pair from what tumble.distance returned: value "
      "k/2 d^2 in penetration (d < 0), zero apart, and its gradients k d (d distance / d pose) "
      "with each component clipped to [-max_gradient, max_gradient].");

  py::class_<tumble::SdfTree>(m, "Sdf")
      .def(py::init([](const py::object& description) {
             return std::make_unique<tumble::SdfTree>(
                 // A field given in code, not a document from elsewhere: its files may lie
                 // anywhere.
                 tumble::load_sdf_string(yaml_of(description, "Sdf"), "Sdf",
                                         {.allow_outside_files = true}));
           }),
           py::arg("description"),
           "A signed distance field from its description as in a scene's `sdf:` field, as a "
           "dict ({'torus': {'major_radius': 1, 'minor_radius': 0.25}}) or YAML text.")
      .def("sample", &sample_field<tumble::SdfTree>, py::arg("points"),
           "The signed distance (negative inside) and its gradient at points (3,) or (N, 3): a "
           "float or an (N,) array, and (3,) or (N, 3).")
      .def_property_readonly(
          "bounds",
          [](const tumble::SdfTree& tree) {
            return py::make_tuple(array_of(tree.bounds().min), array_of(tree.bounds().max));
          },
          "(min, max) corners of a box holding every point inside (infinite where a half-space "
          "leaves it open).")
      .def_property_readonly("exact", &tumble::SdfTree::is_exact,
                             "Whether the value is the distance everywhere (a lone primitive).");

  py::class_<tumble::NeuralSdf>(m, "NeuralSdf")
      .def(py::init([](const py::object& path) {
             return std::make_unique<tumble::NeuralSdf>(
                 tumble::load_neural_sdf_file(path_of(path, "path")));
           }),
           py::arg("path"),
           "A neural signed distance field from its weights file (docs/sdf.md, \"Neural SDFs\"; "
           "examples/python/fit_neural_sdf.py writes one).")
      .def("sample", &sample_field<tumble::NeuralSdf>, py::arg("points"),
           "The network's signed distance and its back-propagated gradient at points (3,) or "
           "(N, 3).")
      .def_property_readonly("bounds", [](const tumble::NeuralSdf& net) {
        return py::make_tuple(array_of(net.bounds().min), array_of(net.bounds().max));
      });

  py::class_<BodyId>(m, "BodyId")
      .def_readonly("index", &BodyId::index)
      .def_readonly("generation", &BodyId::generation)
      .def("__eq__", [](const BodyId& a, const BodyId& b) { return a == b; })
      .def("__repr__", [](const BodyId& b) {
        return "BodyId(" + std::to_string(b.index) + ", " + std::to_string(b.generation) + ")";
      });

  py::class_<tumble::World>(m, "World")
      .def(py::init([](const py::object& scene) {
             return std::make_unique<tumble::World>(scene_from(scene));
           }),
           py::arg("scene"))
      .def("body", &tumble::World::body, py::arg("name"))
      .def("step", py::overload_cast<int>(&tumble::World::step), py::arg("n") = 1)
      .def("reset", py::overload_cast<>(&tumble::World::reset))
      .def_property_readonly("time", &tumble::World::time)
      .def_property_readonly("step_count", &tumble::World::step_count)
      .def("state_hash", &tumble::World::state_hash)
      .def(
          "add_force",
          [](tumble::World& w, BodyId id, const std::vector<Real>& f) {
            w.add_force(id, vec3(f, "force"));
          },
          py::arg("body"), py::arg("force"))
      .def(
          "add_torque",
          [](tumble::World& w, BodyId id, const std::vector<Real>& t) {
            w.add_torque(id, vec3(t, "torque"));
          },
          py::arg("body"), py::arg("torque"))
      .def(
          "apply_impulse",
          [](tumble::World& w, BodyId id, const std::vector<Real>& j, const std::vector<Real>& p) {
            w.apply_impulse(id, vec3(j, "impulse"), vec3(p, "point"));
          },
          py::arg("body"), py::arg("impulse"), py::arg("point"))
      .def(
          "set_velocity",
          [](tumble::World& w, BodyId id, const std::vector<Real>& v, const std::vector<Real>& a) {
            w.set_velocity(id, vec3(v, "velocity"), vec3(a, "angular_velocity"));
          },
          py::arg("body"), py::arg("velocity"), py::arg("angular_velocity"))
      .def(
          "set_kinematic_target",
          [](tumble::World& w, BodyId id, const std::vector<Real>& p, const std::vector<Real>& q) {
            w.set_kinematic_target(id, vec3(p, "position"), quat(q));
          },
          py::arg("body"), py::arg("position"), py::arg("orientation"))
      .def(
          "body_state",
          [](const tumble::World& w, BodyId id) {
            const tumble::BodyState s = w.body_state(id);
            py::array_t<double> out(13);
            double* o = out.mutable_data();
            const double values[13] = {
                s.position.x(),        s.position.y(),         s.position.z(),
                s.orientation.w(),     s.orientation.x(),      s.orientation.y(),
                s.orientation.z(),     s.velocity.x(),         s.velocity.y(),
                s.velocity.z(),        s.angular_velocity.x(), s.angular_velocity.y(),
                s.angular_velocity.z()};
            std::copy(values, values + 13, o);
            return out;
          },
          py::arg("body"), "px py pz qw qx qy qz vx vy vz wx wy wz, as a float64 array")
      .def("contact_reports",
           [](const tumble::World& w) {
             py::list reports;
             for (const tumble::ContactReport& r : w.contact_reports()) {
               py::dict d;
               d["body_a"] = r.body_a;
               d["body_b"] = r.body_b;
               d["normal"] = std::vector<Real>{r.normal.x(), r.normal.y(), r.normal.z()};
               py::list points;
               for (int k = 0; k < r.point_count; ++k) {
                 const tumble::ContactPointReport& p = r.points[std::size_t(k)];
                 py::dict point;
                 point["position"] =
                     std::vector<Real>{p.position.x(), p.position.y(), p.position.z()};
                 point["depth"] = p.depth;
                 point["normal_impulse"] = p.normal_impulse;
                 point["friction_impulse"] = std::vector<Real>{
                     p.friction_impulse.x(), p.friction_impulse.y(), p.friction_impulse.z()};
                 points.append(point);
               }
               d["points"] = points;
               reports.append(d);
             }
             return reports;
           })
      .def(
          "ray_cast",
          [](const tumble::World& w, const std::vector<Real>& origin,
             const std::vector<Real>& direction, Real max_distance) -> py::object {
            const std::optional<tumble::RayHit> hit =
                w.ray_cast(vec3(origin, "origin"), vec3(direction, "direction"), max_distance);
            if (!hit)
              return py::none();
            py::dict d;
            d["body"] = hit->body;
            d["distance"] = hit->distance;
            d["point"] = std::vector<Real>{hit->point.x(), hit->point.y(), hit->point.z()};
            d["normal"] = std::vector<Real>{hit->normal.x(), hit->normal.y(), hit->normal.z()};
            return d;
          },
          py::arg("origin"), py::arg("direction"), py::arg("max_distance"));

  py::class_<BatchWorld>(m, "BatchWorld")
      .def(py::init([](const py::object& scene, int num_worlds, int threads, const py::object& seed,
                       int first_world) {
             return std::make_unique<BatchWorld>(scene_from(scene), num_worlds, threads,
                                                 seed_value(seed, "seed"), first_world);
           }),
           py::arg("scene"), py::arg("num_worlds"), py::arg("threads") = 0, py::arg("seed") = 0,
           py::arg("first_world") = 0,
           "first_world: this batch is a shard of a larger one; its world i draws as world "
           "first_world + i of that batch (tumble/batch_world.hpp).")
      .def_property_readonly("num_worlds", &BatchWorld::size)
      .def_property_readonly("body_count", &BatchWorld::body_count)
      .def_property_readonly("threads", &BatchWorld::threads)
      .def(
          "observe",
          [](py::object self) {
            BatchWorld& b = self.cast<BatchWorld&>();
            return view(const_cast<Real*>(b.observations().data()),
                        {b.size(), b.body_count(), BatchWorld::kObservationWidth}, self, false);
          },
          "A read-only float64 view [worlds, bodies, 13] of px py pz qw qx qy qz vx vy vz wx wy "
          "wz, updated in place by step() and reset().")
      .def(
          "set_forces",
          [](BatchWorld& b, const py::object& f) {
            copy_checked(f, b.forces(), b.size(), b.body_count(), 3, "forces");
          },
          py::arg("forces"), "Forces [worlds, bodies, 3] in N; they stay until set again.")
      .def(
          "set_torques",
          [](BatchWorld& b, const py::object& t) {
            copy_checked(t, b.torques(), b.size(), b.body_count(), 3, "torques");
          },
          py::arg("torques"))
      .def(
          "set_kinematic_targets",
          [](BatchWorld& b, const py::object& targets) {
            copy_checked(targets, b.kinematic_targets(), b.size(), b.body_count(),
                         BatchWorld::kTargetWidth, "targets");
            // Every kinematic body gets its target; the others' rows are ignored.
            const tumble::World& first = b.world(0);
            const std::span<std::uint8_t> set = b.kinematic_target_set();
            for (int w = 0; w < b.size(); ++w)
              for (int i = 0; i < b.body_count(); ++i)
                set[std::size_t(w * b.body_count() + i)] =
                    first.scene().bodies[std::size_t(i)].kinematic ? 1 : 0;
          },
          py::arg("targets"),
          "Targets [worlds, bodies, 7] (px py pz qw qx qy qz) for the kinematic bodies, reached "
          "at the end of the next step; rows of other bodies are ignored.")
      .def(
          // The GIL stays held: another Python thread must not touch the batch's arrays or worlds
          // while they step (the worlds already run on the batch's own threads).
          "step", [](BatchWorld& b, int n) { b.step(n); }, py::arg("n") = 1)
      .def(
          "reset",
          [](BatchWorld& b, const py::object& ids, const py::object& seeds) {
            std::vector<int> list;
            if (ids.is_none()) {
              for (int w = 0; w < b.size(); ++w)
                list.push_back(w);
            } else {
              list = world_ids(ids, b.size());
            }
            if (seeds.is_none()) {
              b.reset(list);
              return;
            }
            const std::vector<std::uint64_t> drawn = seed_list(seeds);
            if (drawn.size() != list.size())
              throw py::value_error("reset: " + std::to_string(drawn.size()) + " seeds for " +
                                    std::to_string(list.size()) + " worlds; give one per world");
            b.reset(list, drawn);
          },
          py::arg("ids") = py::none(), py::arg("seeds") = py::none(),
          "Resets the worlds listed (all when None). A scene with a randomize block draws each "
          "world anew: its next draw, or the draw of its seed in `seeds`.")
      .def(
          "seed", [](const BatchWorld& b, int i) { return b.seed(checked_world(b, i)); },
          py::arg("world"),
          "The seed of the world's current draw (tumble.randomized(scene, seed)).")
      .def(
          "contact_forces",
          [](py::object self) {
            BatchWorld& b = self.cast<BatchWorld&>();
            return view(const_cast<Real*>(b.contact_forces().data()), {b.size(), b.body_count(), 3},
                        self, false);
          },
          "A read-only float64 view [worlds, bodies, 3]: each body's contact force over the last "
          "step, N.")
      .def("contact_counts",
           [](py::object self) {
             BatchWorld& b = self.cast<BatchWorld&>();
             return view(const_cast<std::int32_t*>(b.contact_counts().data()),
                         {b.size(), b.body_count()}, self, false);
           })
      .def(
          "state_hash",
          [](const BatchWorld& b, int i) { return b.state_hash(checked_world(b, i)); },
          py::arg("world"));
}
