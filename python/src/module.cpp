// The compiled part of the Python module (mesodpd._core): the spec reader and validate() of the C++
// library, TOML <-> Python conversion, the api::Simulation facade with zero-copy numpy views of the
// particle arrays, and the units mapper. The pure-Python package (python/mesodpd/) wraps it.
#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <limits>
#include <sstream>
#include <toml++/toml.h>

#include "engine/initial_state.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/flow_numbers.hpp"
#include "mesodpd/simulation.hpp"
#include "mesodpd/units.hpp"
#include "mesodpd/validate.hpp"

namespace py = pybind11;
using namespace mesodpd;

namespace {

// ---- TOML <-> Python, generic (no key of the schema is named here) ----------------------------

py::object to_python(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    py::dict d;
    for (const auto& [k, v] : *t) d[py::str(std::string(k.str()))] = to_python(v);
    return d;
  }
  if (const auto* a = n.as_array()) {
    py::list l;
    for (const auto& v : *a) l.append(to_python(v));
    return l;
  }
  if (const auto* v = n.as_string()) return py::str(v->get());
  if (const auto* v = n.as_integer()) return py::int_(v->get());
  if (const auto* v = n.as_floating_point()) return py::float_(v->get());
  if (const auto* v = n.as_boolean()) return py::bool_(v->get());
  std::ostringstream os;  // dates and times: their TOML text
  if (const auto* v = n.as_date()) os << *v;
  if (const auto* v = n.as_time()) os << *v;
  if (const auto* v = n.as_date_time()) os << *v;
  return py::str(os.str());
}

void insert(toml::table& t, const std::string& key, py::handle v, const std::string& path);

toml::array to_array(py::handle seq, const std::string& path) {
  toml::array a;
  std::size_t k = 0;
  for (py::handle item : seq) {
    const std::string at = path + "[" + std::to_string(k++) + "]";
    toml::table holder;
    insert(holder, "v", item, at);
    if (auto* node = holder.get("v")) a.push_back(std::move(*node));
  }
  return a;
}

// One Python value as a TOML node. None means "not set" (the key is left out).
void insert(toml::table& t, const std::string& key, py::handle v, const std::string& path) {
  if (v.is_none()) return;
  if (py::isinstance<py::bool_>(v)) {
    t.insert_or_assign(key, v.cast<bool>());
  } else if (py::isinstance<py::int_>(v)) {
    // TOML integers are signed 64-bit: a larger Python int is refused with its key, not clamped.
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    if (overflow != 0 || (n == -1 && PyErr_Occurred())) {
      PyErr_Clear();
      throw ConfigError(path + " = " + std::string(py::str(v)) + ": too large for a TOML integer (" +
                            std::to_string(std::numeric_limits<std::int64_t>::min()) + " to " +
                            std::to_string(std::numeric_limits<std::int64_t>::max()) + ")",
                        path);
    }
    t.insert_or_assign(key, static_cast<std::int64_t>(n));
  } else if (py::isinstance<py::float_>(v)) {
    t.insert_or_assign(key, v.cast<double>());
  } else if (py::isinstance<py::str>(v)) {
    t.insert_or_assign(key, v.cast<std::string>());
  } else if (py::isinstance<py::dict>(v)) {
    toml::table sub;
    for (auto [k, item] : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k))
        throw ConfigError(path + ": keys must be strings, got " + std::string(py::str(k)), path);
      const std::string name = k.cast<std::string>();
      insert(sub, name, item, path.empty() ? name : path + "." + name);
    }
    t.insert_or_assign(key, std::move(sub));
  } else if (py::hasattr(v, "tolist")) {  // numpy arrays and scalars
    insert(t, key, v.attr("tolist")(), path);
  } else if (py::isinstance<py::sequence>(v)) {
    t.insert_or_assign(key, to_array(v, path));
  } else {
    throw ConfigError(path + ": cannot be written as TOML (a " +
                          std::string(py::str(v.get_type().attr("__name__"))) + ")",
                      path);
  }
}

py::dict toml_to_dict(const std::string& text, const std::string& source) {
  try {
    return to_python(toml::parse(text, source)).cast<py::dict>();
  } catch (const toml::parse_error& e) {
    throw ConfigError(source + ":" + std::to_string(e.source().begin.line) + ":" +
                      std::to_string(e.source().begin.column) + ": TOML syntax error: " + std::string(e.description()));
  }
}

std::string dict_to_toml(const py::dict& d) {
  toml::table t;
  for (auto [k, item] : d) {
    if (!py::isinstance<py::str>(k)) throw ConfigError("keys must be strings, got " + std::string(py::str(k)));
    const std::string name = k.cast<std::string>();
    insert(t, name, item, name);
  }
  std::ostringstream os;
  os << toml::toml_formatter(t);
  return os.str() + "\n";
}

// ---- numpy helpers ------------------------------------------------------------------------------

// A read-only numpy view of `data` whose base is `owner` (kept alive by the array).
template <class T>
py::array view(std::span<const T> data, py::handle owner) {
  py::array_t<T> a({static_cast<py::ssize_t>(data.size())}, {static_cast<py::ssize_t>(sizeof(T))}, data.data(),
                   owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

// A read-only numpy array that owns a copy of `data`.
template <class T>
py::array frozen_copy(std::span<const T> data) {
  py::array_t<T> a(static_cast<py::ssize_t>(data.size()));
  if (!data.empty()) std::memcpy(a.mutable_data(), data.data(), data.size() * sizeof(T));
  a.attr("flags").attr("writeable") = false;
  return a;
}

template <class T>
py::array copy(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
  return a;
}

py::dict thermo_dict(const api::Thermo& t) {
  py::dict d;
  d["step"] = t.step;
  d["time"] = t.time;
  d["temperature"] = t.temperature;
  d["temperature_transverse"] = t.temperature_transverse;
  d["pressure"] = t.pressure;
  d["pressure_tensor"] = copy(std::vector<double>(t.pressure_tensor.begin(), t.pressure_tensor.end()));
  d["pressure_conservative"] = t.pressure_conservative;
  d["momentum"] = copy(std::vector<double>(t.momentum.begin(), t.momentum.end()));
  d["potential_energy"] = t.potential_energy;
  d["kinetic_energy"] = t.kinetic_energy;
  return d;
}

py::dict history_dict(const std::vector<api::Thermo>& rows) {
  const auto n = static_cast<py::ssize_t>(rows.size());
  py::array_t<std::uint64_t> step(n);
  py::array_t<double> time(n), temp(n), temp_t(n), p(n), pc(n), pe(n), ke(n);
  py::array_t<double> tensor({n, py::ssize_t{6}}), mom({n, py::ssize_t{3}});
  auto st = step.mutable_unchecked<1>();
  auto tm = time.mutable_unchecked<1>(), tt = temp.mutable_unchecked<1>(), ttt = temp_t.mutable_unchecked<1>();
  auto pp = p.mutable_unchecked<1>(), ppc = pc.mutable_unchecked<1>(), ppe = pe.mutable_unchecked<1>(),
       pke = ke.mutable_unchecked<1>();
  auto ten = tensor.mutable_unchecked<2>();
  auto mo = mom.mutable_unchecked<2>();
  for (py::ssize_t k = 0; k < n; ++k) {
    const api::Thermo& r = rows[static_cast<std::size_t>(k)];
    st(k) = r.step;
    tm(k) = r.time;
    tt(k) = r.temperature;
    ttt(k) = r.temperature_transverse;
    pp(k) = r.pressure;
    ppc(k) = r.pressure_conservative;
    ppe(k) = r.potential_energy;
    pke(k) = r.kinetic_energy;
    for (int c = 0; c < 6; ++c) ten(k, c) = r.pressure_tensor[static_cast<std::size_t>(c)];
    for (int c = 0; c < 3; ++c) mo(k, c) = r.momentum[static_cast<std::size_t>(c)];
  }
  py::dict d;
  d["step"] = step;
  d["time"] = time;
  d["temperature"] = temp;
  d["temperature_transverse"] = temp_t;
  d["pressure"] = p;
  d["pressure_tensor"] = tensor;
  d["pressure_conservative"] = pc;
  d["momentum"] = mom;
  d["potential_energy"] = pe;
  d["kinetic_energy"] = ke;
  return d;
}

// ---- the simulation -----------------------------------------------------------------------------

// The base object of a zero-copy particle view (PySimulation::view): holds the simulation alive for as
// long as the view is, and its weak reference tells step() that a view of the engine's memory exists.
struct ViewToken {
  py::object owner;  // the Python Simulation object whose arrays the view reads
  std::string field;
  std::uint64_t step = 0;
};

struct PySimulation {
  api::Simulation sim;
  // Advanced before every single step: a copy of the particle arrays made at an older version is of an
  // older state (LocalParticles caches its copies by it).
  std::uint64_t version = 0;
  // True while a step runs without the GIL: the arrays are then being rewritten and possibly reallocated,
  // so another Python thread must not read them.
  bool stepping = false;
  std::vector<py::weakref> views;  // tokens of the zero-copy views handed out (dead ones pruned lazily)

  PySimulation(const SimulationSpec& spec, const std::string& out, const std::string& restart,
               std::optional<std::uint64_t> final_step, bool progress, bool record)
      : sim(spec, [&] {
          api::Options o;
          o.output_dir = out;
          o.restart = restart;
          o.final_step = final_step;
          o.progress = progress;
          o.record = record;
          return o;
        }()) {}

  void refuse_while_stepping(const char* what) const {
    if (stepping)
      throw std::runtime_error(std::string(what) + ": the simulation is advancing in another thread; read the "
                                                   "particles between steps");
  }

  // The engine may reallocate or reorder every particle array in a step, so it must not step while a
  // zero-copy view of them is still referenced: that view would read freed or reused memory.
  void refuse_live_views() {
    auto prune = [this] {
      std::erase_if(views, [](const py::weakref& w) { return w().is_none(); });
    };
    prune();
    if (views.empty()) return;
    py::module_::import("gc").attr("collect")();  // views kept only by garbage cycles do not count
    prune();
    if (views.empty()) return;
    const ViewToken& t = views.front()().cast<const ViewToken&>();
    throw std::runtime_error(
        "a zero-copy view sim.particles.view('" + t.field + "') taken at step " + std::to_string(t.step) +
        " is still referenced (" + std::to_string(views.size()) +
        " view(s) in all); stepping would leave it reading memory the engine reuses or frees. Delete it (del), "
        "or copy it (numpy.array(v)), before advancing; sim.particles." + t.field +
        " gives a copy that stays valid");
  }

  // Advances n steps one at a time: between two steps the GIL is taken back so that Ctrl-C (SIGINT) and
  // other signals are handled at once, as KeyboardInterrupt, instead of after the whole run.
  void advance(std::uint64_t n) {
    for (std::uint64_t k = 0; k < n; ++k) {
      refuse_live_views();
      ++version;
      {
        stepping = true;
        struct Done {
          bool& flag;
          ~Done() { flag = false; }
        } done{stepping};
        py::gil_scoped_release release;
        sim.step(1);
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
  }
};

// The named particle array of this rank's owned particles, passed to `f` as a span: a fixed field, or a
// model's scalar (temp, conc1, ...; api::Simulation::scalar_field).
template <class F>
decltype(auto) with_field(const api::Simulation& sim, const api::Particles& p, const std::string& name, F&& f) {
  if (name == "id") return f(p.id);
  if (name == "species") return f(p.species);
  const std::pair<const char*, std::span<const double>> reals[] = {
      {"x", p.x}, {"y", p.y}, {"z", p.z}, {"vx", p.vx}, {"vy", p.vy}, {"vz", p.vz}, {"fx", p.fx}, {"fy", p.fy},
      {"fz", p.fz}};
  for (const auto& [n, v] : reals)
    if (name == n) return f(v);
  const std::pair<const char*, std::span<const std::int32_t>> images[] = {{"ix", p.ix}, {"iy", p.iy}, {"iz", p.iz}};
  for (const auto& [n, v] : images)
    if (name == n) return f(v);
  try {
    return f(sim.scalar_field(name));
  } catch (const std::invalid_argument& e) {
    throw py::key_error("no particle array '" + name + "' (" + e.what() + ")");
  }
}

py::dict spec_summary(const SimulationSpec& s) {
  py::dict d;
  d["source"] = s.source;
  d["box"] = s.box;
  d["periodic"] = s.periodic;
  d["kT"] = s.kT;
  d["seed"] = s.seed;
  d["dt"] = s.dt;
  d["steps"] = s.steps;
  d["thermo_every"] = s.thermo_every;
  py::list species;
  for (const SpeciesSpec& sp : s.species) {
    py::dict e;
    e["name"] = sp.name;
    e["mass"] = sp.mass;
    e["count"] = sp.count;
    for (const auto& [key, value] : sp.own) e[py::str(key)] = value;  // the law's species keys (cv, radius, ...)
    species.append(e);
  }
  d["species"] = species;
  py::list pairs;
  for (const PairSpec& p : s.pairs) {
    py::dict e;
    e["species"] = py::make_tuple(s.species[static_cast<std::size_t>(p.i)].name,
                                  s.species[static_cast<std::size_t>(p.j)].name);
    e["a"] = p.a;
    e["gamma"] = p.gamma;
    e["rc"] = p.rc;
    e["rd"] = p.rd;
    e["s"] = p.s;
    pairs.append(e);
  }
  d["pairs"] = pairs;
  return d;
}

py::dict numbers_dict(const FlowNumbers& f) {
  py::dict d;
  d["density"] = f.density;
  d["sound_speed"] = f.sound_speed;
  d["alpha"] = f.alpha;
  d["viscosity"] = f.viscosity;
  d["viscosity_source"] = f.viscosity_source;
  d["diffusion"] = f.diffusion;
  d["schmidt"] = f.schmidt;
  d["flow_speed"] = f.flow_speed;
  d["reynolds"] = f.reynolds;
  d["mach"] = f.mach;
  d["length"] = f.length;
  d["friction_rate"] = f.friction_rate;
  d["thermostat_dt_limit"] = f.thermostat_dt_limit;
  d["warnings"] = f.warnings;
  d["text"] = format_flow_numbers(f);
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "mesodpd compiled core (use the mesodpd package)";
  m.attr("version") = MESODPD_VERSION;
#ifdef MESODPD_HAVE_MPI
  m.attr("has_mpi") = true;
#else
  m.attr("has_mpi") = false;
#endif

  // C++ exceptions become the package's Python exceptions (mesodpd/errors.py), with the key or the step.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const api::BlowUpError& e) {
      py::object cls = py::module_::import("mesodpd.errors").attr("BlowUpError");
      PyErr_SetObject(cls.ptr(), cls(e.what(), e.step(), e.particle_id()).ptr());
    } catch (const ConfigError& e) {
      py::object cls = py::module_::import("mesodpd.errors").attr("SpecError");
      py::object key = e.key().empty() ? py::object(py::none()) : py::object(py::str(e.key()));
      PyErr_SetObject(cls.ptr(), cls(e.what(), key).ptr());
    }
  });

  m.def("toml_to_dict", &toml_to_dict, py::arg("text"), py::arg("source") = "<string>",
        "TOML text -> nested dict (tables -> dict, arrays -> list)");
  m.def("dict_to_toml", &dict_to_toml, py::arg("data"), "nested dict -> TOML text (None values are left out)");

  py::class_<SimulationSpec>(m, "ValidatedSpec", "A SimulationSpec read and validated by the C++ code")
      .def("summary", &spec_summary)
      .def("total_particles",
           [](const SimulationSpec& s) {
             std::uint64_t n = 0;
             for (const auto& sp : s.species) n += sp.count;
             return n;
           })
      .def("check_initial_state", &check_initial_state,
           "what `mesodpd check` does after validation: reads a data file; returns the particle count")
      .def("flow_numbers", [](const SimulationSpec& s) { return numbers_dict(flow_numbers(s)); });
  m.def("parse_spec", &parse_config, py::arg("text"), py::arg("source"),
        "TOML text -> validated spec (raises SpecError naming the key)");
  m.def("load_spec", [](const std::string& path) { return load_config(path); }, py::arg("path"));

  m.def("set_threads", [](int n) { omp_set_num_threads(n); }, py::arg("n"));
  m.def("max_threads", [] { return omp_get_max_threads(); });

  py::class_<ViewToken>(m, "_ViewToken", "base object of a zero-copy particle view (LocalParticles.view)")
      .def_property_readonly("field", [](const ViewToken& t) { return t.field; })
      .def_property_readonly("step", [](const ViewToken& t) { return t.step; });

  py::class_<PySimulation>(m, "Simulation")
      .def(py::init<const SimulationSpec&, const std::string&, const std::string&, std::optional<std::uint64_t>, bool,
                    bool>(),
           py::arg("spec"), py::arg("out"), py::arg("restart"), py::arg("final_step"), py::arg("progress"),
           py::arg("record"))
      .def("step", &PySimulation::advance, py::arg("steps"))
      .def("state_version", [](const PySimulation& s) { return s.version; })
      .def("finish", [](PySimulation& s) { return s.sim.finish(); })
      .def("current_step", [](const PySimulation& s) { return s.sim.current_step(); })
      .def("final_step", [](const PySimulation& s) { return s.sim.final_step(); })
      .def("time", [](const PySimulation& s) { return s.sim.time(); })
      .def("box", [](const PySimulation& s) { return s.sim.box(); })
      .def("total_particles", [](const PySimulation& s) { return s.sim.total_particles(); })
      .def("rank", [](const PySimulation& s) { return s.sim.rank(); })
      .def("ranks", [](const PySimulation& s) { return s.sim.ranks(); })
      .def("spec", [](const PySimulation& s) { return s.sim.spec(); })
      .def("thermo", [](PySimulation& s) { return thermo_dict(s.sim.thermo()); })
      .def("thermo_history", [](const PySimulation& s) { return history_dict(s.sim.thermo_history()); })
      .def("write_checkpoint", [](const PySimulation& s, const std::string& f) { s.sim.write_checkpoint(f); })
      .def("local_count",
           [](const PySimulation& s) {
             s.refuse_while_stepping("len(particles)");
             return s.sim.particles().id.size();
           })
      .def("local_copy",
           [](const PySimulation& s, const std::string& name) -> py::array {
             s.refuse_while_stepping("particles");
             return with_field(s.sim, s.sim.particles(), name, [](auto span) { return frozen_copy(span); });
           })
      .def("set_local",
           [](PySimulation& s, const std::string& name,
              py::array_t<double, py::array::c_style | py::array::forcecast> values) {
             s.refuse_while_stepping("particles.set");
             if (values.ndim() != 1) throw py::value_error("particles.set('" + name + "'): a 1-D array of values");
             try {
               s.sim.set_scalar_field(name, std::span<const double>(values.data(), static_cast<std::size_t>(values.size())));
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
             ++s.version;  // copies made before are of the old values
           })
      .def("local_view",
           [](py::object self, const std::string& name) -> py::array {
             PySimulation& s = self.cast<PySimulation&>();
             s.refuse_while_stepping("particles.view");
             const api::Particles p = s.sim.particles();
             py::object token = py::cast(ViewToken{self, name, s.sim.current_step()});
             py::array a = with_field(s.sim, p, name, [&](auto span) { return view(span, token); });
             s.views.emplace_back(token);
             return a;
           })
      .def("gather",
           [](const PySimulation& s) -> py::object {
             const api::Snapshot g = s.sim.gather();
             if (s.sim.rank() != 0) return py::none();
             py::dict d;
             d["id"] = copy(g.id);
             d["species"] = copy(g.species);
             d["x"] = copy(g.x);
             d["y"] = copy(g.y);
             d["z"] = copy(g.z);
             d["vx"] = copy(g.vx);
             d["vy"] = copy(g.vy);
             d["vz"] = copy(g.vz);
             d["fx"] = copy(g.fx);
             d["fy"] = copy(g.fy);
             d["fz"] = copy(g.fz);
             d["ix"] = copy(g.ix);
             d["iy"] = copy(g.iy);
             d["iz"] = copy(g.iz);
             return d;
           })
      .def("profile",
           [](const PySimulation& s) -> py::object {
             const auto p = s.sim.profile();
             if (!p) return py::none();
             py::dict d;
             d["flow_axis"] = p->flow_axis;
             d["gradient_axis"] = p->gradient_axis;
             d["z"] = copy(p->z);
             d["v_mean"] = copy(p->v_mean);
             d["v_err"] = copy(p->v_err);
             d["v_fit"] = copy(p->v_fit);
             d["eta"] = p->eta;
             d["eta_err"] = p->eta_err;
             d["blocks_used"] = p->blocks_used;
             d["samples"] = p->samples;
             return d;
           })
      .def("rdf",
           [](const PySimulation& s) -> py::object {
             const auto g = s.sim.rdf();
             if (!g) return py::none();
             py::dict d;
             d["r"] = copy(g->r);
             d["g"] = copy(g->g);
             d["samples"] = g->samples;
             return d;
           })
      .def("fields",
           [](const PySimulation& s) {
             py::list out;
             for (const api::Fields& f : s.sim.fields()) {
               py::dict d;
               d["name"] = f.name;
               d["bins"] = f.bins;
               d["samples"] = f.samples;
               d["x"] = copy(f.x);
               d["y"] = copy(f.y);
               d["z"] = copy(f.z);
               d["density"] = copy(f.density);
               d["vx"] = copy(f.vx);
               d["vy"] = copy(f.vy);
               d["vz"] = copy(f.vz);
               d["temperature"] = copy(f.temperature);
               out.append(d);
             }
             return out;
           })
      .def("bodies",
           [](const PySimulation& s) {
             py::list out;
             for (const api::Body& b : s.sim.bodies()) {
               py::dict d;
               d["solid"] = b.solid;
               d["mass"] = b.mass;
               d["particles"] = b.particles;
               d["position"] = copy(std::vector<double>(b.position.begin(), b.position.end()));
               d["orientation"] = copy(std::vector<double>(b.orientation.begin(), b.orientation.end()));
               d["velocity"] = copy(std::vector<double>(b.velocity.begin(), b.velocity.end()));
               d["angular_velocity"] = copy(std::vector<double>(b.angular_velocity.begin(), b.angular_velocity.end()));
               d["force"] = copy(std::vector<double>(b.force.begin(), b.force.end()));
               d["torque"] = copy(std::vector<double>(b.torque.begin(), b.torque.end()));
               d["stresslet"] = copy(std::vector<double>(b.stresslet.begin(), b.stresslet.end()));
               out.append(d);
             }
             return out;
           })
      .def("msd", [](const PySimulation& s) -> py::object {
        const auto g = s.sim.msd();
        if (!g) return py::none();
        py::dict d;
        d["time"] = copy(g->time);
        d["msd"] = copy(g->msd);
        d["diffusion"] = g->diffusion;
        return d;
      });

  // ---- units mapper (mesodpd/units.hpp) ----
  py::class_<units::PhysicalSystem>(m, "PhysicalSystem")
      .def(py::init<>())
      .def_readwrite("coarse_graining", &units::PhysicalSystem::coarse_graining)
      .def_readwrite("temperature", &units::PhysicalSystem::temperature)
      .def_readwrite("molar_mass", &units::PhysicalSystem::molar_mass)
      .def_readwrite("molecular_volume", &units::PhysicalSystem::molecular_volume)
      .def_readwrite("mass_density", &units::PhysicalSystem::mass_density)
      .def_readwrite("inverse_compressibility", &units::PhysicalSystem::inverse_compressibility)
      .def_readwrite("isothermal_compressibility", &units::PhysicalSystem::isothermal_compressibility)
      .def_readwrite("viscosity", &units::PhysicalSystem::viscosity)
      .def_readwrite("self_diffusion", &units::PhysicalSystem::self_diffusion)
      .def_readwrite("chi", &units::PhysicalSystem::chi)
      .def_readwrite("dpd_density", &units::PhysicalSystem::dpd_density)
      .def_readwrite("alpha", &units::PhysicalSystem::alpha)
      .def_readwrite("gamma", &units::PhysicalSystem::gamma)
      .def_readwrite("dpd_viscosity", &units::PhysicalSystem::dpd_viscosity)
      .def_readwrite("dpd_diffusion", &units::PhysicalSystem::dpd_diffusion)
      .def_readwrite("time_from", &units::PhysicalSystem::time_from);

  py::class_<units::Mapping>(m, "Mapping")
      .def_readonly("a_ii", &units::Mapping::a_ii)
      .def_readonly("delta_a", &units::Mapping::delta_a)
      .def_readonly("a_ij", &units::Mapping::a_ij)
      .def_readonly("alpha", &units::Mapping::alpha)
      .def_readonly("alpha_source", &units::Mapping::alpha_source)
      .def_readonly("inverse_compressibility", &units::Mapping::inverse_compressibility)
      .def_readonly("length", &units::Mapping::length)
      .def_readonly("mass", &units::Mapping::mass)
      .def_readonly("energy", &units::Mapping::energy)
      .def_readonly("time", &units::Mapping::time)
      .def_readonly("time_source", &units::Mapping::time_source)
      .def_readonly("thermal_time", &units::Mapping::thermal_time)
      .def_readonly("dpd_viscosity", &units::Mapping::dpd_viscosity)
      .def_readonly("dpd_diffusion", &units::Mapping::dpd_diffusion)
      .def_readonly("dpd_transport_source", &units::Mapping::dpd_transport_source)
      .def_readonly("notes", &units::Mapping::notes)
      .def("to_si", &units::Mapping::to_si, py::arg("value"), py::arg("quantity"))
      .def("from_si", &units::Mapping::from_si, py::arg("value"), py::arg("quantity"))
      .def("unit", &units::Mapping::unit, py::arg("quantity"))
      .def("text", [](const units::Mapping& mp) { return units::format_mapping(mp); });
  m.def("map_units", &units::map_units, py::arg("system"));
  m.def("water_300k", &units::water_300k);
  m.def("measured_alpha", &units::measured_alpha, py::arg("density"));
  m.def("unit_quantities", &units::quantities);
}
