// The `lieservo` Python module (pybind11): the groups, concentrated Gaussians and their fusion,
// and the discriminative Bayes filter, in double precision, with NumPy arrays in and out.
//
// Conventions are the library's (docs/conventions.md): ξ = [ρ; φ] translation first, left
// perturbation X = exp(ε^) X̄, radians. A Status other than ok becomes a lieservo.Error (a
// ValueError) whose `status` names the code; the object it was called on is left unchanged.
// Shapes are checked by pybind11's Eigen casters: a 4×4 for SE(3), 6-vectors for its tangent;
// anything else raises TypeError naming the expected signature.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <lieservo/lieservo.hpp>

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>

namespace py = pybind11;
using namespace lieservo;

namespace {

/// Raises TypeError unless `src` holds numbers: NumPy would turn an object array (None → NaN),
/// strings (parsed) and complex numbers (imaginary part dropped) into doubles silently.
void requireNumeric(py::handle src, const char* what) {
  // An ndarray's dtype is read directly (the common case, no copy); anything else goes through
  // numpy.asarray first, as pybind11's conversion would.
  const py::array a = py::isinstance<py::array>(src) ? py::reinterpret_borrow<py::array>(src)
                                                      : py::array(py::module_::import("numpy").attr("asarray")(src));
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    throw py::type_error(std::string(what) + ": expected real numbers, got an array of dtype " +
                         py::str(a.dtype()).cast<std::string>());
}

/// A fixed-size Eigen argument whose elements are checked to be real numbers before pybind11's
/// Eigen conversion (which checks the shape).
template <class T>
struct Checked {
  T value;
};

}  // namespace

namespace pybind11::detail {
template <class T>
struct type_caster<Checked<T>> {
  PYBIND11_TYPE_CASTER(Checked<T>, make_caster<T>::name);
  bool load(handle src, bool convert) {
    if (convert && !src.is_none()) requireNumeric(src, "lieservo: an array argument");
    make_caster<T> inner;
    if (!inner.load(src, convert)) return false;
    value.value = cast_op<T&&>(std::move(inner));
    return true;
  }
  static handle cast(const Checked<T>& v, return_value_policy policy, handle parent) {
    return make_caster<T>::cast(v.value, policy, parent);
  }
};
}  // namespace pybind11::detail

namespace {

/// Raised for every Status other than ok (outlier_rejected is reported, not raised).
struct StatusError {
  Status status;
  std::string where;
};

const char* statusName(Status s) {
  switch (s) {
    case Status::ok: return "ok";
    case Status::non_finite_input: return "non_finite_input";
    case Status::not_orthonormal: return "not_orthonormal";
    case Status::not_spd: return "not_spd";
    case Status::invalid_time_step: return "invalid_time_step";
    case Status::not_initialised: return "not_initialised";
    case Status::invalid_argument: return "invalid_argument";
    case Status::outlier_rejected: return "outlier_rejected";
    case Status::not_converged: return "not_converged";
    case Status::numerical_failure: return "numerical_failure";
    case Status::io_error: return "io_error";
    case Status::end_of_stream: return "end_of_stream";
    case Status::device_error: return "device_error";
  }
  return "unknown";
}

void check(Status s, const char* where) {
  if (s != Status::ok) throw StatusError{s, where};
}

/// The fusion form named in Python: "information" or "square_root".
FusionForm fusionForm(const std::string& name, const char* where) {
  if (name == "information") return FusionForm::information;
  if (name == "square_root") return FusionForm::square_root;
  throw py::value_error(std::string(where) + ": form must be 'information' or 'square_root', got '" + name + "'");
}

template <class G>
G checkedFromMatrix(const Checked<typename G::Matrix>& M) {
  G out;
  check(G::fromMatrix(M.value, out), "from_matrix");
  return out;
}

template <class G>
G checkedFromMatrixProjected(const Checked<typename G::Matrix>& M) {
  G out;
  check(G::fromMatrixProjected(M.value, out), "from_matrix_projected");
  return out;
}

/// A matrix as a 2-D array whatever its size: pybind11 would hand a 1×1 Eigen matrix (SO(2)'s
/// Jacobians) back as a 1-D array.
template <class M>
py::array_t<double> matrix2d(const M& m) {
  py::array_t<double> a({py::ssize_t(m.rows()), py::ssize_t(m.cols())});
  auto o = a.template mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) o(r, c) = m(r, c);
  return a;
}

/// Rows of an (N, D) float64 array, C-contiguous (NumPy converts other layouts on the way in).
using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `src` as Rows: refuses what is not real numbers (TypeError); NumPy's own conversion, so that
/// an allocation failure (a huge broadcast array) raises MemoryError.
Rows rowsOf(const py::object& src, const char* what) {
  requireNumeric(src, what);
  py::object a = py::module_::import("numpy").attr("ascontiguousarray")(src, py::dtype::of<double>());
  return Rows::ensure(a);
}

void requireShape(const Rows& a, std::initializer_list<py::ssize_t> tail, const char* what) {
  const auto nd = static_cast<std::size_t>(a.ndim());
  bool ok = nd == tail.size() + 1;
  std::size_t k = 1;
  for (py::ssize_t t : tail) ok = ok && a.shape(static_cast<py::ssize_t>(k++)) == t;
  if (!ok) {
    std::ostringstream m;
    m << what << ": expected an array of shape (N";
    for (py::ssize_t t : tail) m << ", " << t;
    m << "), got ndim " << nd;
    throw py::value_error(m.str());
  }
}

/// The methods every group shares; `name` is the Python class name.
template <class G>
py::class_<G> bindGroup(py::module_& m, const char* name, const char* doc) {
  using Tangent = typename G::Tangent;
  using Matrix = typename G::Matrix;
  using Jacobian = typename G::Jacobian;
  static constexpr int D = G::DoF;  // static: lambdas use them without capturing
  static constexpr int N = static_cast<int>(Matrix::RowsAtCompileTime);
  py::class_<G> c(m, name, doc);
  c.def(py::init<>(), "The identity.")
      .def_static("identity", &G::identity)
      .def_static("exp", [](const Checked<Tangent>& xi) { return G::exp(xi.value); }, py::arg("xi"),
                  "exp(ξ^): the element of the tangent vector ξ (translation first, radians).")
      .def("log", [](const G& X) { return Tangent(X.log()); }, "ln(X)^∨, principal branch.")
      .def("inverse", &G::inverse)
      .def("Ad", [](const G& X) { return matrix2d(Jacobian(X.Ad())); }, "The adjoint matrix Ad(X).")
      .def_static("ad", [](const Checked<Tangent>& xi) { return matrix2d(Jacobian(G::ad(xi.value))); }, py::arg("xi"))
      .def_static("hat", [](const Checked<Tangent>& xi) { return Matrix(G::hat(xi.value)); }, py::arg("xi"))
      .def_static("vee", [](const Checked<Matrix>& M) { return Tangent(G::vee(M.value)); }, py::arg("M"))
      .def_static("left_jacobian", [](const Checked<Tangent>& xi) { return matrix2d(Jacobian(G::leftJacobian(xi.value))); },
                  py::arg("xi"), "J(ξ), closed form (eq. 33, eqn:left_jacobian_def).")
      .def_static("left_jacobian_inverse",
                  [](const Checked<Tangent>& xi) { return matrix2d(Jacobian(G::leftJacobianInverse(xi.value))); }, py::arg("xi"))
      .def("matrix", [](const G& X) { return Matrix(X.matrix()); }, "The homogeneous (or rotation) matrix.")
      .def_static("from_matrix", &checkedFromMatrix<G>, py::arg("M"),
                  "Checked: finite, homogeneous bottom row, and a rotation block C with ‖CᵀC − I‖_F ≤ √ε (1.5e-8) and det C > 0.")
      .def_static("from_matrix_projected", &checkedFromMatrixProjected<G>, py::arg("M"),
                  "The nearest element to M (rotation block projected onto the group).")
      .def("__mul__", [](const G& a, const G& b) { return G(a * b); }, py::is_operator())
      .def("compose", [](const G& a, const G& b) { return G(a * b); }, py::arg("other"))
      .def("act", [](const G& X, const Checked<typename G::Point>& p) { return typename G::Point(X * p.value); }, py::arg("p"),
           "X·p for a point p.")
      .def("lplus", [](const G& X, const Checked<Tangent>& e) { return lplus(X, e.value); }, py::arg("eps"),
           "X ⊕ ε = exp(ε^) X.")
      .def("lminus", [](const G& X, const G& Y) { return Tangent(lminus(X, Y)); }, py::arg("Y"),
           "X ⊖ Y = ln(X Y⁻¹)^∨.")
      .def("is_approx", [](const G& a, const G& b, double tol) { return a.isApprox(b, tol); }, py::arg("other"),
           py::arg("tol") = 1e-12)
      .def("__repr__", [name](const G& X) {
        std::ostringstream s;
        s << name << "(\n" << X.matrix() << ")";
        return s.str();
      });
  c.attr("dof") = D;
  // Batches: one call for N elements, where a Python loop would dominate. The C-contiguous
  // arrays are read and written in place through row-major maps of each element.
  using RowMajor = Eigen::Matrix<double, N, N, (N > 1 ? Eigen::RowMajor : Eigen::ColMajor)>;
  using In = Eigen::Map<const RowMajor>;
  using Out = Eigen::Map<RowMajor>;
  // The checked element of A[k]; throws StatusError naming `what`.
  auto element = [](const double* A, py::ssize_t k, const char* what) {
    G X;
    const Status s = G::fromMatrix(Matrix(In(A + k * N * N)), X);
    if (s != Status::ok) throw StatusError{s, what};
    return X;
  };
  c.def_static(
      "exp_batch",
      [](const py::object& xi_in) {
        const Rows xi = rowsOf(xi_in, "exp_batch");
        requireShape(xi, {D}, "exp_batch");
        const py::ssize_t n = xi.shape(0);
        py::array_t<double> out({n, py::ssize_t(N), py::ssize_t(N)});
        const double* in = xi.data();
        double* o = out.mutable_data();
        py::gil_scoped_release free_gil;  // raw buffers only from here
        for (py::ssize_t k = 0; k < n; ++k) Out(o + k * N * N) = G::exp(Eigen::Map<const Tangent>(in + k * D)).matrix();
        return out;
      },
      py::arg("xi"), "exp of each row of an (N, dof) array: an (N, n, n) array of matrices.");
  c.def_static(
      "log_batch",
      [element](const py::object& Ms_in) {
        const Rows Ms = rowsOf(Ms_in, "log_batch");
        requireShape(Ms, {N, N}, "log_batch");
        const py::ssize_t n = Ms.shape(0);
        py::array_t<double> out({n, py::ssize_t(D)});
        const double* in = Ms.data();
        double* o = out.mutable_data();
        py::gil_scoped_release free_gil;
        for (py::ssize_t k = 0; k < n; ++k) Eigen::Map<Tangent>(o + k * D) = element(in, k, "log_batch").log();
        return out;
      },
      py::arg("M"), "log of each (checked) matrix of an (N, n, n) array: an (N, dof) array.");
  c.def_static(
      "compose_batch",
      [element](const py::object& A_in, const py::object& B_in) {
        const Rows A = rowsOf(A_in, "compose_batch"), B = rowsOf(B_in, "compose_batch");
        requireShape(A, {N, N}, "compose_batch");
        requireShape(B, {N, N}, "compose_batch");
        if (A.shape(0) != B.shape(0)) throw py::value_error("compose_batch: A and B differ in length");
        const py::ssize_t n = A.shape(0);
        py::array_t<double> out({n, py::ssize_t(N), py::ssize_t(N)});
        const double *a = A.data(), *b = B.data();
        double* o = out.mutable_data();
        py::gil_scoped_release free_gil;
        for (py::ssize_t k = 0; k < n; ++k)
          Out(o + k * N * N) = (element(a, k, "compose_batch") * element(b, k, "compose_batch")).matrix();
        return out;
      },
      py::arg("A"), py::arg("B"), "A[k]·B[k] for (N, n, n) arrays of (checked) matrices.");
  return c;
}

/// ConcentratedGaussian<G>, fromTangentGaussian, fuse and the filter for one group.
template <class G>
void bindEstimation(py::module_& m, const std::string& suffix) {
  using Gaussian = ConcentratedGaussian<G>;
  using Tangent = typename G::Tangent;
  using Jacobian = typename G::Jacobian;
  const std::string gname = "ConcentratedGaussian" + suffix;
  py::class_<Gaussian>(m, gname.c_str(),
                       "X = exp(ε^) X̄ with ε ~ N(0, Σ): `mean` (a group element), `covariance`.")
      .def(py::init([](const G& mean, const Checked<Jacobian>& covariance) {
             Gaussian g;
             g.mean = mean;
             g.covariance = covariance.value;
             check(g.validate(), "ConcentratedGaussian");
             return g;
           }),
           py::arg("mean"), py::arg("covariance"), "Checked: a valid mean and an SPD covariance.")
      .def_property_readonly("mean", [](const Gaussian& g) { return g.mean; })
      .def_property_readonly("covariance", [](const Gaussian& g) { return matrix2d(g.covariance); });

  m.def(
      ("from_tangent_gaussian" + suffix).c_str(),
      [](const Checked<Tangent>& mu, const Checked<Tangent>& sigma) {
        Gaussian out;
        check(fromTangentGaussian(mu.value, sigma.value, out), "from_tangent_gaussian");  // DefaultJacobian, as Filter
        return out;
      },
      py::arg("mu"), py::arg("sigma"),
      "A network's (μ, σ) as a concentrated Gaussian: X̄ = exp(μ^), Σ = J(μ) diag(σ²) J(μ)ᵀ "
      "(eq. 14, eq:se3_inverse_transform), J by the paper's second-order series as in the filter's fusion.");

  m.def(
      ("fuse" + suffix).c_str(),
      [](const Gaussian& a, const Gaussian& b, int max_iterations, double tolerance, bool require_convergence,
         const std::string& jacobian, const std::string& form) {
        FusionOptions<double> o;
        o.max_iterations = max_iterations;
        o.tolerance = tolerance;
        o.require_convergence = require_convergence;
        o.form = fusionForm(form, "fuse");
        FusionResult<G> r;
        Status s;
        if (jacobian != "paper" && jacobian != "closed_form")
          throw py::value_error("fuse: jacobian must be 'paper' or 'closed_form', got '" + jacobian + "'");
        {
          py::gil_scoped_release free_gil;  // a and b are not changed; r is this call's own
          s = jacobian == "paper" ? fuse<PaperJacobian>(a, b, o, r) : fuse<ClosedFormJacobian>(a, b, o, r);
        }
        check(s, "fuse");
        py::dict d;
        d["fused"] = r.fused;
        d["iterations"] = r.iterations;
        d["step_norm"] = r.step_norm;
        d["step_sigmas"] = r.step_sigmas;
        d["converged"] = r.converged;
        d["max_rotation_separation"] = r.max_rotation_separation;
        return d;
      },
      py::arg("a"), py::arg("b"), py::arg("max_iterations") = 5, py::arg("tolerance") = 0.0,
      py::arg("require_convergence") = true, py::arg("jacobian") = "paper", py::arg("form") = "information",
      "The normalised product of two concentrated Gaussians (Algorithm 3, alg:se3_data_fusion). tolerance > 0: "
      "stop once an update is shorter than that many standard deviations of the result (0: exactly "
      "max_iterations updates, the paper's 5); require_convergence: whether not meeting it raises. form: "
      "'information' (default; hands ill-conditioned factors to the square-root form) or 'square_root'. "
      "Returns a dict: fused, iterations, step_norm, step_sigmas, converged, max_rotation_separation.");

  using Filter = DiscriminativeBayesFilter<G, DefaultJacobian>;
  const std::string fname = "DiscriminativeBayesFilter" + suffix;
  py::class_<Filter>(m, fname.c_str(),
                     "The discriminative Bayes filter (Algorithm 2, alg:se3_bayes_filter), series J⁻¹ N = 2 as the paper.")
      .def(py::init([](const py::object& process_noise, int max_iterations, double tolerance,
                       bool require_convergence, bool gating, double gate_probability, const std::string& form) {
             typename Filter::Options o;
             if (!process_noise.is_none()) {
               requireNumeric(process_noise, "DiscriminativeBayesFilter: process_noise");
               const py::array a = py::module_::import("numpy").attr("asarray")(process_noise, py::dtype::of<double>());
               if (a.ndim() != 2 || a.shape(0) != G::DoF || a.shape(1) != G::DoF) {
                 std::ostringstream m;
                 m << "DiscriminativeBayesFilter: process_noise must be a (" << G::DoF << ", " << G::DoF
                   << ") array, got shape (";
                 for (py::ssize_t i = 0; i < a.ndim(); ++i) m << (i ? ", " : "") << a.shape(i);
                 m << ")";
                 throw py::value_error(m.str());
               }
               o.process_noise = a.cast<Jacobian>();
             }
             o.fusion.max_iterations = max_iterations;
             o.fusion.tolerance = tolerance;
             o.fusion.require_convergence = require_convergence;
             o.fusion.form = fusionForm(form, "DiscriminativeBayesFilter");
             o.gating = gating;
             o.gate_probability = gate_probability;
             check(Filter::validate(o), "DiscriminativeBayesFilter");
             return Filter(o);
           }),
           py::arg("process_noise") = py::none(), py::arg("max_iterations") = 5, py::arg("tolerance") = 0.0,
           py::arg("require_convergence") = true, py::arg("gating") = false, py::arg("gate_probability") = 0.999,
           py::arg("form") = "information",
           "process_noise: Σφ (default: the paper's σφ = 0.5 mm and 0.5°, in radians); max_iterations, tolerance, "
           "require_convergence: the fusion's iteration control as lieservo.fuse (the paper: 5, 0; the converged "
           "rule: tolerance=0.001, require_convergence=False); form: the fusion's 'information' (default) or "
           "'square_root' form.")
      .def(
          "step",
          [](Filter& f, const G& sensor_pose, const Gaussian& observation) {
            Status s;
            {
              py::gil_scoped_release free_gil;  // one filter object per thread (docs/python.md)
              s = f.step(sensor_pose, observation);
            }
            if (s == Status::outlier_rejected) return false;
            check(s, "step");
            return true;
          },
          py::arg("sensor_pose"), py::arg("observation"),
          "One filter step; the first initialises. Returns True, or False when the gate rejected the "
          "observation (the state is then the prediction). Raises lieservo.Error otherwise, state unchanged.")
      .def(
          "predict",
          [](Filter& f, const G& T_bar) { check(f.predict(T_bar), "predict"); }, py::arg("T_bar"),
          "The prediction alone, with the relative motion T̄_k = X_k⁻¹ X_{k−1} of the sensor poses, the "
          "inverse of the odometry increment (eq. 12, eqn:bayes_filter_prediction).")
      .def(
          "predict_from_odometry",
          [](Filter& f, const G& increment) { check(f.predictFromOdometry(increment), "predict_from_odometry"); },
          py::arg("increment"),
          "The prediction alone, from the sensor's odometry increment X_{k−1}⁻¹ X_k (the new sensor pose in "
          "the previous sensor frame): predict(increment.inverse()).")
      .def(
          "correct",
          [](Filter& f, const Gaussian& observation) {
            const Status s = f.correct(observation);
            if (s == Status::outlier_rejected) return false;
            check(s, "correct");
            return true;
          },
          py::arg("observation"), "The correction alone (data fusion with the belief); False when gated.")
      .def("reset", &Filter::reset)
      .def_property_readonly("initialised", &Filter::initialised)
      .def_property_readonly("filtered", [](const Filter& f) { return f.filtered(); }, "The filtered Gaussian.")
      .def_property_readonly("belief", [](const Filter& f) { return f.belief(); }, "The predicted Gaussian of the latest step.")
      .def_property_readonly("diagnostics", [](const Filter& f) {
        const auto& d = f.diagnostics();
        py::dict r;
        r["last_status"] = statusName(d.last_status);
        r["iterations"] = d.iterations;
        r["step_norm"] = d.step_norm;
        r["step_sigmas"] = d.step_sigmas;
        r["converged"] = d.converged;
        r["nis"] = d.nis;
        r["gated"] = d.gated;
        r["corrections"] = d.corrections;
        r["rejected"] = d.rejected;
        return r;
      });
}

using Vec6 = Eigen::Matrix<double, 6, 1>;

PaperGainConvention convention(double control_period) {
  if (!(control_period > 0.0) || !std::isfinite(control_period))
    throw py::value_error("control_period must be finite and > 0 (seconds)");
  PaperGainConvention c;
  c.control_period = control_period;
  return c;
}

/// The paper's controllers (Tables 6-9) on SE(3), double.
// The tactile loop (control/tactile_loop.hpp) for one controller: made from a filter and a
// controller object (their options; the loop starts uninitialised), stepped once a frame.
template <class Controller>
void bindLoop(py::module_& m, const char* name, const char* controller_name) {
  using Loop = TactileLoop<Controller>;
  using Filter = DiscriminativeBayesFilter<SE3d, DefaultJacobian>;
  const std::string doc = std::string("The tactile loop (docs/control.md, section 8): the Bayes filter and a ") +
                          controller_name + ", stepped together under one policy.";
  py::class_<Loop>(m, name, doc.c_str())
      .def(py::init([](const Filter& filter, const Controller& controller) {
             const typename Loop::Options o{filter.options(), controller.options()};
             check(Loop::validate(o), "TactileLoop");
             return Loop(o);
           }),
           py::arg("filter"), py::arg("controller"),
           "A new loop with the filter's and the controller's options (neither object is changed or shared).")
      .def(
          "step",
          [](Loop& loop, const SE3d& sensor_pose, const ConcentratedGaussian<SE3d>& observation, double dt) {
            Vec6 u;
            Status s;
            {
              py::gil_scoped_release free_gil;  // one loop object per thread
              s = loop.step(sensor_pose, observation, dt, u);
            }
            check(s, "step");
            return u;
          },
          py::arg("sensor_pose"), py::arg("observation"), py::arg("dt"),
          "One tactile frame: X_ws, the observation of X_sf and dt > 0 → the sensor body twist. Raises "
          "lieservo.Error when refused (nothing changed); outcome says what an accepted step did.")
      .def("reset", &Loop::reset, "The filter forgets and the controller is cleared (options kept).")
      .def_property_readonly(
          "outcome", [](const Loop& loop) { return std::string(describe(loop.outcome())); },
          "'initialised', 'commanded', 'gated' (the prediction used), 'terminated' or 'refused'.")
      .def_property_readonly("terminated", &Loop::terminated)
      .def_property_readonly("filtered", [](const Loop& loop) { return loop.filter().filtered(); },
                             "The filtered ConcentratedGaussian of X_sf.");
}

void bindControl(py::module_& m) {
  using Pid = MimoPid<double, 6>;
  py::class_<Pid>(m, "MimoPid", "The 6-channel PID with feedforward (eq. 19, eqn:ff_fb_pid_control), diagonal gains.")
      .def(py::init([](const Checked<Vec6>& kp, const Checked<Vec6>& ki, const Checked<Vec6>& kd, double integral_clip,
                       double output_clip, double smoothing) {
             Pid::Options o = Pid::Options::diagonal(kp.value, ki.value, kd.value);
             o.clipIntegral(-integral_clip, integral_clip).clipOutput(-output_clip, output_clip);
             o.smoothing = smoothing;
             check(Pid::validate(o), "MimoPid");
             return Pid(o);
           }),
           py::arg("kp"), py::arg("ki"), py::arg("kd"), py::arg("integral_clip") = INFINITY,
           py::arg("output_clip") = INFINITY, py::arg("smoothing") = 1.0,
           "Gains per channel (kp 1/s, ki 1/s², kd dimensionless), symmetric clips of ∫e dt and u, and the "
           "per-step weight α ∈ (0, 1] of the newest error in the smoothed error (1 = none).")
      .def(
          "step",
          [](Pid& pid, const Checked<Vec6>& error, const Checked<Vec6>& feedforward, double dt) {
            Vec6 u;
            check(pid.step(error.value, feedforward.value, dt, u), "step");
            return u;
          },
          py::arg("error"), py::arg("feedforward"), py::arg("dt"))
      .def("reset", &Pid::reset);

  using Servo = TactileServoController<SE3d>;
  py::class_<Servo>(m, "TactileServoController",
                    "Feedforward-feedback PID in the tangent space (Section 3.3.2, sec:servoing_controller).")
      .def(py::init([](const std::string& preset, double control_period) {
             const PaperGainConvention c = convention(control_period);
             Servo::Options o;
             if (preset == "object_tracking")
               o = objectTrackingPreset<double>(c);
             else if (preset == "surface_following")
               o = surfaceFollowingPreset<double>(c);
             else if (preset == "stabiliser")
               o = stabiliserPreset<double>(false, c);
             else if (preset == "stabiliser_tall")
               o = stabiliserPreset<double>(true, c);
             else
               throw py::value_error("TactileServoController: preset must be object_tracking, surface_following, "
                                     "stabiliser or stabiliser_tall, got '" + preset + "'");
             return Servo(o);
           }),
           py::arg("preset") = "object_tracking", py::arg("control_period") = 0.05,
           "A paper preset (Table 6: object_tracking; 7: surface_following; 9: stabiliser, stabiliser_tall) "
           "with its per-step gains converted at control_period (s).")
      .def(
          "step",
          [](Servo& c, const SE3d& feature_in_sensor, double dt) {
            Vec6 u;
            check(c.step(feature_in_sensor, dt, u), "step");
            return u;
          },
          py::arg("feature_in_sensor"), py::arg("dt"),
          "One cycle: X_sf (filtered) and dt > 0 → the sensor body twist u = [v (mm/s); ω (rad/s)].")
      .def("set_reference", [](Servo& c, const SE3d& X) { check(c.setReference(X), "set_reference"); },
           py::arg("reference_sensor_in_feature"))
      .def("set_feedforward", [](Servo& c, const Checked<Vec6>& v) { check(c.setFeedforward(v.value), "set_feedforward"); },
           py::arg("feedforward_in_reference"))
      .def("reset", &Servo::reset)
      .def_property_readonly("tangent_error", [](const Servo& c) { return Vec6(c.tangentError()); })
      .def_property_readonly("reference", [](const Servo& c) { return c.options().reference; });

  m.def("surface_following_feedforward",
        [](double heading, double speed) { return Vec6(surfaceFollowingFeedforward<double>(heading, speed)); },
        py::arg("heading"), py::arg("speed") = paper::kSurfaceFollowingSpeed,
        "u_s'2 = (speed cos θ, speed sin θ, 0, 0, 0, 0) for a heading θ (rad), speed in mm/s.");

  using Push = PushingController<SE3d>;
  py::class_<Push>(m, "PushingController", "Tactile pushing towards a target (Section 3.3.3, sec:pushing_controller, Table 8).")
      .def(py::init([](const std::string& configuration, const SE3d& target, double control_period) {
             PushingConfiguration k;
             if (configuration == "single_arm")
               k = PushingConfiguration::single_arm;
             else if (configuration == "dual_arm_leader")
               k = PushingConfiguration::dual_arm_leader;
             else if (configuration == "dual_arm_leader_tall_object")
               k = PushingConfiguration::dual_arm_leader_tall_object;
             else
               throw py::value_error("PushingController: configuration must be single_arm, dual_arm_leader or "
                                     "dual_arm_leader_tall_object, got '" + configuration + "'");
             Push::Options o = pushingPreset<double>(k, convention(control_period));
             o.target = target;
             check(Push::validate(o), "PushingController");
             return Push(o);
           }),
           py::arg("configuration") = "single_arm", py::arg("target") = SE3d(), py::arg("control_period") = 0.05)
      .def(
          "step",
          [](Push& c, const SE3d& sensor_in_work, const SE3d& feature_in_sensor, double dt) {
            Vec6 u;
            check(c.step(sensor_in_work, feature_in_sensor, dt, u), "step");
            return u;
          },
          py::arg("sensor_in_work"), py::arg("feature_in_sensor"), py::arg("dt"),
          "One cycle: X_ws, X_sf (filtered), dt > 0 → the sensor body twist (zero once terminated).")
      .def("set_target", [](Push& c, const SE3d& X) { check(c.setTarget(X), "set_target"); }, py::arg("target_in_work"))
      .def("reset", &Push::reset)
      .def_property_readonly("terminated", &Push::terminated)
      .def_property_readonly("bearing", &Push::bearing, "Target bearing (rad) of the last step.")
      .def_property_readonly("distance", &Push::distance, "Target distance (mm) of the last step.");

  using Dual = DualArmPushing<SE3d>;
  py::class_<Dual>(m, "DualArmPushing",
                   "Leader pushing (Table 8) and follower stabiliser (Table 9), each with its own filter.")
      .def(py::init([](bool tall_object, const SE3d& target, double control_period) {
             Dual::Options o = dualArmPushingPreset<double>(tall_object, convention(control_period));
             o.leader.target = target;
             check(Dual::validate(o), "DualArmPushing");
             return Dual(o, DiscriminativeBayesFilter<SE3d>(), DiscriminativeBayesFilter<SE3d>());
           }),
           py::arg("tall_object") = false, py::arg("target") = SE3d(), py::arg("control_period") = 0.05)
      .def(
          "step",
          [](Dual& d, const SE3d& leader_pose, const ConcentratedGaussian<SE3d>& leader_observation,
             const SE3d& follower_pose, const ConcentratedGaussian<SE3d>& follower_observation, double dt) {
            Dual::ArmInput li, fi;
            li.sensor_pose = leader_pose;
            li.observation = leader_observation;
            fi.sensor_pose = follower_pose;
            fi.observation = follower_observation;
            Dual::ArmOutput lo, fo;
            check(d.step(li, fi, dt, lo, fo), "step");
            py::dict r;
            r["leader_velocity"] = Vec6(lo.velocity);
            r["follower_velocity"] = Vec6(fo.velocity);
            r["leader_feature_in_sensor"] = lo.feature_in_sensor;
            r["follower_feature_in_sensor"] = fo.feature_in_sensor;
            r["leader_gated"] = lo.outcome == LoopOutcome::gated;
            r["follower_gated"] = fo.outcome == LoopOutcome::gated;
            return r;
          },
          py::arg("leader_pose"), py::arg("leader_observation"), py::arg("follower_pose"),
          py::arg("follower_observation"), py::arg("dt"),
          "Filters both observations and steps both controllers; returns a dict of both twists and filtered poses.")
      .def("reset", &Dual::reset);

  bindLoop<TactileServoController<SE3d>>(m, "TactileLoop", "TactileServoController");
  bindLoop<PushingController<SE3d>>(m, "PushingLoop", "PushingController");
}

}  // namespace

// `_lieservo`, imported by the package's __init__.py (examples/python/lieservo_package) as `lieservo`.
PYBIND11_MODULE(_lieservo, m) {
  m.doc() = "lieservo: Lie groups, concentrated Gaussians, fusion and the discriminative Bayes filter "
            "of pose-and-shear tactile servoing (double precision).";
  m.attr("__version__") = LIESERVO_VERSION_STRING;  // package.xml's, through CMake
  static py::exception<StatusError> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const StatusError& e) {
      PyObject* type = error.ptr();
      py::object inst = py::reinterpret_steal<py::object>(
          PyObject_CallFunction(type, "s", (std::string(e.where) + ": " + describe(e.status) + " (" +
                                            statusName(e.status) + ")").c_str()));
      if (!inst) return;  // the Python error set by the failed call propagates
      inst.attr("status") = statusName(e.status);
      PyErr_SetObject(type, inst.ptr());
    }
  });

  bindGroup<SO2d>(m, "SO2", "Rotations of the plane; tangent: [θ].");
  bindGroup<SE2d>(m, "SE2", "Rigid motions of the plane; tangent: [ρx, ρy, θ].")
      .def_property_readonly("translation", [](const SE2d& X) { return Eigen::Vector2d(X.translation()); });
  auto so3 = bindGroup<SO3d>(m, "SO3", "Rotations; tangent: φ (axis·angle, radians).");
  so3.def("quaternion", [](const SO3d& R) {
       const auto q = R.unitQuaternion();
       return Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
     }, "Unit quaternion [w, x, y, z], w ≥ 0.")
      .def_static("from_quaternion", [](const Checked<Eigen::Vector4d>& wxyz_in) {
        const Eigen::Vector4d& wxyz = wxyz_in.value;
        // Scaled by its largest component first: the squared norm of [1e155, 1e155, 0, 0]
        // overflows and that of [1e-160, 1e-160, 0, 0] underflows, either way a NaN rotation.
        const double big = wxyz.cwiseAbs().maxCoeff();
        if (!wxyz.allFinite() || !(big > 0.0)) throw StatusError{Status::invalid_argument, "from_quaternion"};
        const Eigen::Vector4d q = wxyz / big;
        return SO3d::fromQuaternion(Eigen::Quaterniond(q(0), q(1), q(2), q(3)));
      }, py::arg("wxyz"), "From a non-zero quaternion [w, x, y, z] (normalised).");
  auto se3 = bindGroup<SE3d>(m, "SE3", "Rigid motions; tangent: ξ = [ρ; φ] (translation first).");
  se3.def(py::init([](const SO3d& R, const Checked<Eigen::Vector3d>& t) { return SE3d(R, t.value); }), py::arg("rotation"),
          py::arg("translation"))
      .def_property_readonly("rotation", [](const SE3d& X) { return X.so3(); })
      .def_property_readonly("translation", [](const SE3d& X) { return Eigen::Vector3d(X.translation()); })
      .def_static("from_euler_xyz6_degrees", [](const Checked<Eigen::Matrix<double, 6, 1>>& e_in) {
        const Eigen::Matrix<double, 6, 1>& e = e_in.value;
        if (!e.allFinite()) throw StatusError{Status::non_finite_input, "from_euler_xyz6_degrees"};
        return SE3d::fromEulerXYZ6Degrees(e);
      }, py::arg("e"), "From (x, y, z, α, β, γ): extrinsic x-y-z Euler angles in degrees (the data set's labels).");

  bindEstimation<SE3d>(m, "");
  bindEstimation<SE2d>(m, "_se2");
  bindEstimation<SO3d>(m, "_so3");

  bindControl(m);

  m.def("paper_process_noise", []() { return Eigen::Matrix<double, 6, 6>(paperProcessNoise<SE3d>()); },
        "Σφ of the paper's state dynamics on SE(3): σ = 0.5 mm and 0.5° (in radians).");
}
