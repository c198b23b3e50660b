"""pytest: the lieservo Python module (examples/python) against the library's properties.

Run by CTest as python.bindings (label python) with PYTHONPATH=<build>/python. Seeded; bounds
written before the runs.
"""
import math

import numpy as np
import pytest

import lieservo as ls

RNG = np.random.default_rng(20261124)
GROUPS = [ls.SO2, ls.SE2, ls.SO3, ls.SE3]


def random_tangent(G, n, rot_max=3.0, trans_scale=50.0):
    """n tangent vectors with rotation angle below rot_max (principal branch of log)."""
    d = G.dof
    xi = RNG.normal(size=(n, d)) * trans_scale
    if G in (ls.SO2, ls.SE2):
        xi[:, -1] = RNG.uniform(-rot_max, rot_max, size=n)
    else:
        axis = RNG.normal(size=(n, 3))
        axis /= np.linalg.norm(axis, axis=1, keepdims=True)
        xi[:, -3:] = axis * RNG.uniform(0, rot_max, size=(n, 1))
    return xi


@pytest.mark.parametrize("G", GROUPS)
def test_log_inverts_exp_on_many_samples(G):
    xi = random_tangent(G, 20000)
    back = G.log_batch(G.exp_batch(xi))
    assert np.max(np.abs(back - xi)) < 1e-9


@pytest.mark.parametrize("G", GROUPS)
def test_batch_functions_equal_single_calls(G):
    xi = random_tangent(G, 200)
    Ms = G.exp_batch(xi)
    for k in range(0, 200, 17):
        assert np.array_equal(Ms[k], G.exp(xi[k]).matrix())
    A, B = Ms[:100], Ms[100:]
    C = G.compose_batch(A, B)
    assert np.max(np.abs(C - A @ B)) < 1e-12


@pytest.mark.parametrize("G", GROUPS)
def test_adjoint_moves_a_perturbation_through_the_element(G):
    # X exp(ξ^) X⁻¹ = exp((Ad(X) ξ)^)
    for x, e in zip(random_tangent(G, 100), random_tangent(G, 100, rot_max=0.5, trans_scale=5)):
        X = G.exp(x)
        lhs = (X * G.exp(e) * X.inverse()).matrix()
        rhs = G.exp(X.Ad() @ e).matrix()
        assert np.max(np.abs(lhs - rhs)) < 1e-9


@pytest.mark.parametrize("G", [ls.SE3, ls.SO3, ls.SE2])
def test_left_jacobian_against_central_differences(G):
    # exp((ξ + δ)^) ≈ exp((J(ξ) δ)^) exp(ξ^): column j of J from ±h steps.
    h = 1e-6
    for x in random_tangent(G, 20, rot_max=2.5, trans_scale=2):
        X = G.exp(x)
        J = G.left_jacobian(x)
        num = np.zeros_like(J)
        for j in range(G.dof):
            d = np.zeros(G.dof)
            d[j] = h
            num[:, j] = (G.exp(x + d).lminus(X) - G.exp(x - d).lminus(X)) / (2 * h)
        assert np.max(np.abs(num - J)) < 1e-6
        assert np.max(np.abs(G.left_jacobian_inverse(x) @ J - np.eye(G.dof))) < 1e-10


def test_lplus_and_lminus_are_inverse():
    for x, e in zip(random_tangent(ls.SE3, 100), random_tangent(ls.SE3, 100, rot_max=3.0)):
        X = ls.SE3.exp(x)
        assert np.max(np.abs(X.lplus(e).lminus(X) - e)) < 1e-9


def test_so2_jacobians_are_1x1_matrices():
    X = ls.SO2.exp(np.array([0.3]))
    assert X.Ad().shape == (1, 1) and ls.SO2.left_jacobian(np.array([0.3])).shape == (1, 1)


def test_quaternion_round_trip_and_act():
    for x in random_tangent(ls.SO3, 100):
        R = ls.SO3.exp(x)
        q = R.quaternion()
        assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-14
        assert ls.SO3.from_quaternion(3.0 * q).is_approx(R, 1e-12)
        p = RNG.normal(size=3)
        assert np.max(np.abs(R.act(p) - R.matrix() @ p)) < 1e-12


def test_fusion_euclidean_limit_is_the_product_of_gaussians():
    # Pure translations with tiny rotational spread: the product of two Gaussians.
    S1 = np.diag([4.0, 1.0, 9.0, 1e-10, 1e-10, 1e-10])
    S2 = np.diag([1.0, 4.0, 1.0, 1e-10, 1e-10, 1e-10])
    m1 = ls.SE3(ls.SO3(), np.array([1.0, 2.0, 3.0]))
    m2 = ls.SE3(ls.SO3(), np.array([2.0, -1.0, 0.0]))
    r = ls.fuse(ls.ConcentratedGaussian(m1, S1), ls.ConcentratedGaussian(m2, S2),
                max_iterations=20, tolerance=1e-9, jacobian="closed_form")
    I1, I2 = np.linalg.inv(S1[:3, :3]), np.linalg.inv(S2[:3, :3])
    S = np.linalg.inv(I1 + I2)
    mu = S @ (I1 @ m1.translation + I2 @ m2.translation)
    assert np.max(np.abs(r["fused"].mean.translation - mu)) < 1e-9
    assert np.max(np.abs(r["fused"].covariance[:3, :3] - S)) < 1e-9
    assert r["iterations"] >= 1


def test_fusion_forms_agree_and_a_bad_form_is_refused():
    # Criterion: on realistic factors the two forms give the same fused mean and covariance to
    # 1e-12 (relative), in fuse() and in the filter, but not bitwise (so the argument reaches the
    # library: the forms round differently); an unknown form is a ValueError.
    a = ls.from_tangent_gaussian(np.array([0.3, -0.2, 3.0, 0.02, -0.01, 0.05]),
                                 np.array([0.4, 0.5, 0.2, 0.01, 0.02, 0.03]))
    b = ls.from_tangent_gaussian(np.array([0.1, 0.1, 3.2, 0.01, 0.0, 0.03]),
                                 np.array([0.6, 0.3, 0.3, 0.02, 0.01, 0.02]))
    ri = ls.fuse(a, b)
    rs = ls.fuse(a, b, form="square_root")
    assert np.max(np.abs(ri["fused"].mean.matrix() - rs["fused"].mean.matrix())) < 1e-12
    Si, Ss = ri["fused"].covariance, rs["fused"].covariance
    assert np.linalg.norm(Si - Ss) <= 1e-12 * np.linalg.norm(Ss)
    assert not np.array_equal(Si, Ss)
    fi, fs = ls.DiscriminativeBayesFilter(), ls.DiscriminativeBayesFilter(form="square_root")
    for f in (fi, fs):
        assert f.step(ls.SE3(), a)
        assert f.step(ls.SE3.exp(np.array([0.1, 0, 0, 0, 0, 0.01])), b)
    assert np.linalg.norm(fi.filtered.covariance - fs.filtered.covariance) <= 1e-12 * np.linalg.norm(fs.filtered.covariance)
    assert not np.array_equal(fi.filtered.covariance, fs.filtered.covariance)
    with pytest.raises(ValueError, match="form"):
        ls.fuse(a, b, form="cholesky")
    with pytest.raises(ValueError, match="form"):
        ls.DiscriminativeBayesFilter(form="")


def test_bad_shapes_and_values_raise_clear_errors():
    with pytest.raises(TypeError):
        ls.SE3.exp(np.zeros(5))
    with pytest.raises(TypeError):
        ls.SE3.from_matrix(np.eye(3))
    with pytest.raises(ValueError, match="shape"):
        ls.SE3.exp_batch(np.zeros((4, 5)))
    with pytest.raises(ls.Error) as e:
        ls.SE3.from_matrix(np.diag([2.0, 1.0, 1.0, 1.0]))
    assert e.value.status == "not_orthonormal"
    M = np.eye(4)
    M[0, 3] = np.nan
    with pytest.raises(ls.Error) as e:
        ls.SE3.log_batch(M[None])
    assert e.value.status == "non_finite_input"
    with pytest.raises(ls.Error) as e:
        ls.from_tangent_gaussian(np.zeros(6), np.array([1, 1, 0.0, 1, 1, 1]))
    assert e.value.status == "not_spd"
    with pytest.raises(ls.Error):
        ls.ConcentratedGaussian(ls.SE3(), -np.eye(6))
    with pytest.raises(ValueError, match="jacobian"):
        g = ls.from_tangent_gaussian(np.zeros(6), np.ones(6))
        ls.fuse(g, g, jacobian="nope")
    with pytest.raises(ls.Error):
        ls.DiscriminativeBayesFilter(max_iterations=0)


def test_filter_state_unchanged_after_an_error():
    f = ls.DiscriminativeBayesFilter()
    obs = ls.from_tangent_gaussian(np.array([0, 0, 3.0, 0.1, 0, 0]), np.array([0.5, 0.5, 0.5, 0.02, 0.02, 0.02]))
    assert f.step(ls.SE3(), obs)
    assert f.step(ls.SE3.exp(np.array([0.1, 0, 0, 0, 0, 0])), obs)
    before_mean = f.filtered.mean.matrix().copy()
    before_cov = f.filtered.covariance.copy()
    bad_pose = ls.SE3.exp(np.array([np.nan, 0, 0, 0, 0, 0]))
    with pytest.raises(ls.Error) as e:
        f.step(bad_pose, obs)
    assert e.value.status == "non_finite_input"
    assert np.array_equal(f.filtered.mean.matrix(), before_mean)
    assert np.array_equal(f.filtered.covariance, before_cov)
    assert f.diagnostics["last_status"] == "non_finite_input"


def test_predict_from_odometry_is_predict_of_the_inverse_increment():
    obs = ls.from_tangent_gaussian(np.array([0, 0, 3.0, 0.1, 0, 0]), np.array([0.5, 0.5, 0.5, 0.02, 0.02, 0.02]))
    increment = ls.SE3.exp(np.array([0.4, -0.2, 0.1, 0.01, 0.02, -0.03]))  # X_{k-1}^-1 X_k
    fa, fb = ls.DiscriminativeBayesFilter(), ls.DiscriminativeBayesFilter()
    assert fa.step(ls.SE3(), obs) and fb.step(ls.SE3(), obs)
    fa.predict(increment.inverse())
    fb.predict_from_odometry(increment)
    assert fa.belief.mean.is_approx(fb.belief.mean, 1e-12)
    assert np.allclose(fa.belief.covariance, fb.belief.covariance, rtol=1e-12, atol=0)
    before = fb.belief.mean.matrix().copy()
    with pytest.raises(ls.Error) as e:
        fb.predict_from_odometry(ls.SE3.exp(np.array([np.nan, 0, 0, 0, 0, 0])))
    assert e.value.status == "non_finite_input"
    assert np.array_equal(fb.belief.mean.matrix(), before)


def test_filter_reduces_the_error_of_noisy_observations_of_a_still_contact():
    # A sensor at rest on a contact ξ_true, so the dynamics model has (almost) no process
    # noise; observations with σ = (0.5 mm, 2°). Averaging k observations divides the error by
    # √k, so over steps 50-100 the filtered translation error must be below half the raw
    # observations' (Monte Carlo, seeded). (With the paper's process noise, σφ = 0.5 mm per
    # step as large as the observation noise, the steady-state gain keeps ≈ 0.8 of the error.)
    sigma = np.array([0.5, 0.5, 0.5, math.radians(2), math.radians(2), math.radians(2)])
    truth = np.array([1.0, -0.5, 3.0, 0.1, -0.05, 0.2])
    X_true = ls.SE3.exp(truth)
    f = ls.DiscriminativeBayesFilter(process_noise=1e-8 * np.eye(6))
    raw_err, filt_err = [], []
    for k in range(100):
        mu = truth + RNG.normal(size=6) * sigma
        f.step(ls.SE3(), ls.from_tangent_gaussian(mu, sigma))
        raw_err.append(np.linalg.norm(ls.SE3.exp(mu).lminus(X_true)[:3]))
        filt_err.append(np.linalg.norm(f.filtered.mean.lminus(X_true)[:3]))
    assert np.mean(filt_err[50:]) < 0.5 * np.mean(raw_err[50:])


def test_gate_rejects_an_outlier_and_reports_it():
    f = ls.DiscriminativeBayesFilter(gating=True)
    sigma = np.full(6, 0.01)
    assert f.step(ls.SE3(), ls.from_tangent_gaussian(np.zeros(6), sigma))
    assert f.step(ls.SE3(), ls.from_tangent_gaussian(np.zeros(6), sigma))
    far = np.array([50.0, 0, 0, 0, 0, 0])
    assert f.step(ls.SE3(), ls.from_tangent_gaussian(far, sigma)) is False
    assert f.diagnostics["gated"] and f.diagnostics["rejected"] == 1


# ---- controllers --------------------------------------------------------------------------

def test_pid_is_proportional_with_feedforward():
    kp = np.array([1.0, 2, 3, 4, 5, 6])
    pid = ls.MimoPid(kp=kp, ki=np.zeros(6), kd=np.zeros(6))
    e = np.array([0.1, -0.2, 0.3, 0.01, 0.02, -0.03])
    v = np.array([1.0, 0, 0, 0, 0, 0.5])
    assert np.max(np.abs(pid.step(e, v, 0.05) - (kp * e + v))) < 1e-15
    with pytest.raises(ls.Error) as err:
        pid.step(e, v, 0.0)
    assert err.value.status == "invalid_time_step"
    with pytest.raises(ls.Error):
        ls.MimoPid(kp=kp, ki=kp, kd=kp, smoothing=0.0)


def test_servo_at_its_reference_commands_nothing_and_moves_towards_it_otherwise():
    c = ls.TactileServoController("object_tracking")
    X_ref = c.reference                      # X_fs' (6 mm depth, Table 6)
    # The filtered X_sf equal to the reference's inverse: no error, no twist.
    u = c.step(X_ref.inverse(), 0.05)
    assert np.max(np.abs(u)) < 1e-12
    # The sensor 2 mm too deep (X_fs = X_ref with z 8 mm): the z velocity must reduce the depth.
    X_fs = ls.SE3(ls.SO3(), X_ref.translation + np.array([0, 0, 2.0]))
    c.reset()
    u = c.step(X_fs.inverse(), 0.05)
    assert u[2] < 0
    assert np.all(np.isfinite(u))


def test_servo_refuses_bad_input_and_keeps_its_state():
    c = ls.TactileServoController("surface_following")
    c.set_feedforward(ls.surface_following_feedforward(np.pi / 2))
    X = ls.SE3.exp(np.array([0.1, 0.2, -3.0, 0.05, 0.0, 0.0]))
    c.step(X, 0.05)
    before = c.tangent_error.copy()
    with pytest.raises(ls.Error) as e:
        c.step(X, -1.0)
    assert e.value.status == "invalid_time_step"
    with pytest.raises(ls.Error) as e:
        c.step(ls.SE3.exp(np.array([np.inf, 0, 0, 0, 0, 0])), 0.05)
    assert e.value.status == "non_finite_input"
    assert np.array_equal(c.tangent_error, before)
    with pytest.raises(ValueError, match="preset"):
        ls.TactileServoController("nope")
    with pytest.raises(ValueError, match="control_period"):
        ls.TactileServoController("object_tracking", control_period=0.0)


def test_pushing_terminates_at_the_target():
    target = ls.SE3(ls.SO3(), np.array([0.0, 0.0, 10.0]))       # 10 mm ahead of the sensor
    c = ls.PushingController("single_arm", target=target)
    u = c.step(ls.SE3(), ls.SE3(), 0.05)
    assert c.terminated and np.array_equal(u, np.zeros(6))
    far = ls.PushingController("single_arm", target=ls.SE3(ls.SO3(), np.array([0.0, 100.0, 300.0])))
    u = far.step(ls.SE3(), ls.SE3(), 0.05)
    assert not far.terminated and u[2] > 0                     # pushes along its axis
    assert abs(far.distance - math.hypot(100.0, 300.0)) < 1e-9


def test_dual_arm_step_returns_both_twists():
    d = ls.DualArmPushing(tall_object=True, target=ls.SE3(ls.SO3(), np.array([0.0, 100.0, 300.0])))
    sigma = np.array([0.3, 0.3, 0.3, 0.01, 0.01, 0.01])
    obs = ls.from_tangent_gaussian(np.array([0, 0, 3.0, 0, 0, 0]), sigma)
    r = d.step(ls.SE3(), obs, ls.SE3.exp(np.array([0, 0, 200.0, 0, np.pi, 0])), obs, 0.05)
    assert np.all(np.isfinite(r["leader_velocity"])) and np.all(np.isfinite(r["follower_velocity"]))
    assert not r["leader_gated"] and not r["follower_gated"]
    with pytest.raises(ls.Error):
        d.step(ls.SE3(), obs, ls.SE3(), obs, float("nan"))


def test_tactile_loop_equals_the_filter_then_the_controller_and_refuses_without_change():
    sigma = np.array([0.3, 0.3, 0.3, 0.01, 0.01, 0.01])
    servo = ls.TactileServoController("surface_following")
    servo.set_feedforward(ls.surface_following_feedforward(np.pi / 2))
    loop = ls.TactileLoop(ls.DiscriminativeBayesFilter(gating=True), servo)
    f = ls.DiscriminativeBayesFilter(gating=True)
    outcomes = []
    for k in range(30):
        X_ws = ls.SE3.exp(np.array([0.5 * k, 0, 0, 0, 0, 0.002 * k]))
        mu = np.array([0.2, -0.1, -3.0, 0.01, 0.0, 0.02]) + RNG.normal(size=6) * sigma
        if k == 20:
            mu[1] += 30.0                                       # a misread image: the gate rejects it
        obs = ls.from_tangent_gaussian(mu, sigma)
        u = loop.step(X_ws, obs, 0.05)
        f.step(X_ws, obs)
        assert np.array_equal(u, servo.step(f.filtered.mean, 0.05))  # bit for bit
        outcomes.append(loop.outcome)
    assert outcomes[0] == "initialised" and outcomes[20] == "gated" and outcomes[21] == "commanded"
    before = loop.filtered.mean.log()
    with pytest.raises(ls.Error) as e:
        loop.step(ls.SE3(), obs, 0.0)
    assert e.value.status == "invalid_time_step"
    assert loop.outcome == "refused" and np.array_equal(loop.filtered.mean.log(), before)
    push = ls.PushingLoop(ls.DiscriminativeBayesFilter(),
                          ls.PushingController("single_arm", target=ls.SE3(ls.SO3(), np.array([0.0, 0.0, 10.0]))))
    u = push.step(ls.SE3(), obs, 0.05)
    assert push.terminated and push.outcome == "terminated" and np.array_equal(u, np.zeros(6))


def test_the_module_refuses_what_is_not_real_numbers_and_extreme_quaternions():
    # Quaternions whose squared norm overflows or underflows are normalised, not turned to NaN.
    R = ls.SO3.from_quaternion(np.array([1e155, 1e155, 0, 0]))
    assert np.all(np.isfinite(R.matrix()))
    assert R.is_approx(ls.SO3.from_quaternion(np.array([1.0, 1.0, 0, 0])), 1e-15)
    assert ls.SO3.from_quaternion(np.array([1e-160, 1e-160, 0, 0])).is_approx(R, 1e-15)
    with pytest.raises(ls.Error):
        ls.SO3.from_quaternion(np.zeros(4))
    # Object, string and complex arrays: TypeError, single calls and batches alike.
    for bad in (np.array([1, None, 3, 0, 0, 0], dtype=object), np.array(["1", "2", "3", "0", "0", "0"]),
                np.array([1, 2, 3, 0, 0, 0], dtype=complex)):
        with pytest.raises(TypeError, match="real numbers"):
            ls.SE3.exp(bad)
        with pytest.raises(TypeError, match="real numbers"):
            ls.SE3.exp_batch(bad[None])
    with pytest.raises(TypeError, match="real numbers"):
        ls.SE3(ls.SO3(), [1, 2, None])
    # A process noise of the wrong shape names the expected one.
    with pytest.raises(ValueError, match=r"\(6, 6\)"):
        ls.DiscriminativeBayesFilter(process_noise=np.eye(5))
    with pytest.raises(ValueError, match=r"\(3, 3\)"):
        ls.DiscriminativeBayesFilter_so3(process_noise=np.eye(6))
    # A batch too large to convert raises MemoryError, not a signature mismatch.
    with pytest.raises(MemoryError):
        ls.SE3.exp_batch(np.broadcast_to(np.zeros(6), (10**11, 6)))


def test_batch_functions_let_other_python_threads_run():
    # While exp_batch works through two million rows, another Python thread keeps counting:
    # the GIL is released during the batch (docs/python.md, "Threads"). Held, the counter could
    # not move between the two reads around the call.
    import threading
    import time
    xs = RNG.normal(size=(2_000_000, 6))
    done = threading.Event()
    counter = [0]

    def count():
        while not done.is_set():
            counter[0] += 1

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    # The counter's own rate, while this thread sleeps.
    c0, t0 = counter[0], time.perf_counter()
    time.sleep(0.1)
    rate = (counter[0] - c0) / (time.perf_counter() - t0)
    before = counter[0]
    started = time.perf_counter()
    ls.SE3.exp_batch(xs)
    elapsed = time.perf_counter() - started
    during = counter[0] - before
    done.set()
    t.join()
    # With the GIL held the counter moves only in the switch interval around the call (measured:
    # under 1 % of its rate over the call); released, at about its full rate.
    assert elapsed > 0.05
    assert during > 0.25 * rate * elapsed, (during, rate, elapsed)
