// lieservo.sim — one simulated pushing trial for Python: what a study (study.py) runs in each of
// its Dask tasks. The trial is the demo's own (runPushTrial, judged by judgeTrial), so a study's
// rates are the demo's criteria over more trials.
//
//   >>> from lieservo import sim
//   >>> [c["name"] for c in sim.cases() if c["judged"]][:2]
//   ['pushing_single_foam_blue_square', 'pushing_single_foam_red_square']
//   >>> r = sim.push_trial("pushing_single_foam_blue_square", seed=7, observations="gaussian",
//   ...                    skin_friction=0.7)     # a parameter left out keeps the trial's own draw
//   >>> r["passed"], r["target_error"]
//
// Errors are Python exceptions and run nothing: ValueError for an unknown case, a parameter out
// of its range or an unknown observation mode; RuntimeError when the observations cannot be set up.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "lieservo_sim/tasks.hpp"
#include "programs/observation_setup.hpp"

namespace py = pybind11;
namespace sim = lieservo::sim;

namespace {

constexpr double kDrawn = std::numeric_limits<double>::quiet_NaN();

const sim::NamedPushingCase& findCase(const std::string& name) {
  static const std::vector<sim::NamedPushingCase> cases = sim::pushingCases();
  for (const sim::NamedPushingCase& c : cases)
    if (c.name == name) return c;
  throw py::value_error("unknown pushing case '" + name + "' (lieservo.sim.cases() lists them)");
}

// The observations of each mode, set up once per process as the demo sets them up
// (programs/observation_setup.hpp). The real mode's source runs one trial at a time.
std::mutex g_mutex;

const sim::TaskOptions& baseOptions(const std::string& mode) {
  static std::map<std::string, sim::TaskOptions> by_mode;
  if (auto it = by_mode.find(mode); it != by_mode.end()) return it->second;
  if (mode != "gaussian" && mode != "real")
    throw py::value_error("observations: '" + mode + "' is neither 'gaussian' nor 'real'");
  sim::programs::ObservationChoice choice;
  choice.mode = mode;
  sim::TaskOptions opt;
  std::string note;
  if (sim::programs::setUpObservations(choice, opt, note) != -1)
    throw std::runtime_error("observations '" + mode + "' cannot be set up (the message above says why)");
  return by_mode.emplace(mode, opt).first->second;
}

py::dict pushTrial(const std::string& name, std::uint64_t seed, const std::string& observations,
                   double support_friction_scale, double skin_friction, double gel_stiffness, double start_offset,
                   double start_yaw_deg) {
  const sim::NamedPushingCase& c = findCase(name);
  sim::PushTrial t;
  {
    py::gil_scoped_release free_python;  // the Dask worker's own threads go on while the trial runs
    std::lock_guard<std::mutex> lock(g_mutex);
    sim::TaskOptions opt = baseOptions(observations);
    opt.seed = seed;
    opt.support_friction_scale = support_friction_scale;
    if (!std::isnan(skin_friction)) opt.contact.skin_friction = skin_friction;
    if (!std::isnan(gel_stiffness)) opt.contact.gel_stiffness = gel_stiffness;
    opt.start_offset = start_offset;
    opt.start_yaw = std::isnan(start_yaw_deg) ? kDrawn : lieservo::deg2rad(start_yaw_deg);
    opt.validate();  // SceneError (→ ValueError) names the parameter
    t = sim::runPushTrial(c.setup, opt, seed);
    if (sim::programs::observationsFailed(opt)) throw std::runtime_error("a real observation failed (see above)");
  }
  const sim::PushVerdict v = sim::judgeTrial(c.setup, t);
  py::dict r;
  r["passed"] = v.passed();
  r["reached"] = v.reached;
  r["within_error"] = v.within_error;
  r["contact_kept"] = v.contact_kept;
  r["follower_contact_kept"] = v.follower_contact_kept;
  r["upright"] = v.upright;
  r["opposed"] = v.opposed;
  r["target_error"] = t.target_error;        // mm
  r["final_distance"] = t.final_distance;    // mm
  r["duration"] = t.duration;                // s, simulated
  r["max_tilt"] = t.max_tilt;                // deg
  r["min_opposition"] = t.min_opposition;    // deg
  r["support_friction"] = t.support_friction;
  r["skin_friction"] = t.skin_friction;
  r["gel_stiffness"] = t.gel_stiffness;      // N/mm
  r["start_offset"] = t.start_offset;        // mm
  r["start_yaw_deg"] = lieservo::rad2deg(t.start_yaw);
  return r;
}

}  // namespace

PYBIND11_MODULE(sim, m) {
  m.doc() = "lieservo's simulated pushing trials (examples/sim), one per call: the studies' unit of work";
  py::register_exception<sim::SceneError>(m, "SceneError", PyExc_ValueError);
  m.def(
      "cases",
      [] {
        py::list out;
        for (const sim::NamedPushingCase& c : sim::pushingCases()) {
          py::dict d;
          d["name"] = c.name;
          d["object"] = c.setup.object.name;
          d["surface"] = c.setup.surface.name;
          d["dual_arm"] = c.setup.dual_arm;
          d["centralised"] = c.setup.centralised;
          d["tall"] = c.setup.tall;
          d["judged"] = c.judged;
          out.append(d);
        }
        return out;
      },
      "Every pushing case the demo runs, in its order: name, object, surface, dual_arm, centralised, tall, judged.");
  m.def("push_trial", &pushTrial, py::arg("case"), py::arg("seed"), py::arg("observations") = "gaussian",
        py::arg("support_friction_scale") = kDrawn, py::arg("skin_friction") = kDrawn,
        py::arg("gel_stiffness") = kDrawn, py::arg("start_offset") = kDrawn, py::arg("start_yaw_deg") = kDrawn,
        "One seeded trial of `case` (the same seed gives the same result). A parameter left NaN is drawn "
        "as the demo's trial draws it; observations: 'gaussian' (the calibrated model) or 'real'. Returns "
        "the verdict per criterion ('passed': all of them) and the trial's figures.");
  m.attr("criteria") =
      py::make_tuple("reached", "within_error", "contact_kept", "follower_contact_kept", "upright", "opposed");
}
