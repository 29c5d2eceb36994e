"""Guaranteed fault detection and isolation (issue 24 point 3, setbound.fault): no false alarm on
fault-free data (random and vertex disturbances, zonotopic and ellipsoidal detectors), detection
of injected faults of growing size once they exceed what the set width hides, never an alarm
before the fault, isolation by a bank of hypotheses, and clear errors."""
import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import setbound
from setbound import LinearSystem
from setbound.ellipsoidal import ImprovedEstimator, KalmanFilter, OnlineEstimator, design_offline
from setbound.fault import (Fault, FaultBank, actuator_loss, detect, nominal, parameter_change, sensor_bias,
                            simulate_faulty, stuck_sensor)
from setbound.sets import Ellipsoid, Zonotope
from setbound.zonotopic import SegmentMinEstimator, VolumeMinEstimator
from zono_examples import ex_le13 as le13




def with_input():
    """A plant driven by a known input (for actuator faults)."""
    A = np.array([[0.6, 0.2], [-0.1, 0.7]])
    return LinearSystem(A, [[1.0, 0.0], [0.0, 1.0]], B=[[1.0], [0.5]], E=0.05 * np.eye(2, 4),
                        F=np.hstack([np.zeros((2, 2)), 0.05 * np.eye(2)]))


X0 = Zonotope([0, 0], 3 * np.eye(2))
E0 = Ellipsoid(np.eye(2), [0, 0], 18.0)


def detectors(s):
    d = design_offline(s)
    return {"segment": lambda: SegmentMinEstimator(s, X0), "volume": lambda: VolumeMinEstimator(s, X0),
            "online": lambda: OnlineEstimator(d, E0), "improved": lambda: ImprovedEstimator(d, E0)}


@pytest.mark.parametrize("disturbance", ["uniform", "vertex"])
def test_no_false_alarm_on_fault_free_data(disturbance):
    s = le13()
    for name, make in detectors(s).items():
        for seed in range(3):
            sim = simulate_faulty(s, X0, 300, [], disturbance=disturbance, rng=seed)
            det = detect(make(), sim.y)
            assert det.alarm is None, (name, seed, det.alarm)
            assert not det.flagged.any() and np.all(det.margin <= 0)


def test_sensor_bias_of_growing_size_is_detected_once_it_exceeds_the_set_width():
    s = le13()
    start, N = 60, 160
    for name, make in detectors(s).items():
        delays = []
        for mag in (0.05, 0.5, 1.0, 2.0, 5.0):
            sim = simulate_faulty(s, X0, N, [Fault("sensor_bias", start=start, output=0, magnitude=mag)], rng=4,
                                  disturbance="vertex")
            det = detect(make(), sim.y)
            assert det.alarm is None or det.alarm >= start, (name, mag)  # never before the fault
            delays.append(det.delay(start))
        # 2 and 5 (10 and 25 noise bounds) are beyond every estimator's output-set width:
        # detected at once. Smaller ones are detected when the set is tight enough (the volume
        # minimiser sees 0.05 with vertex noise, the ellipsoids do not): docs/fault_detection.md.
        assert delays[3] is not None and delays[3] <= 2, (name, delays)
        assert delays[4] == 0, (name, delays)


def test_simulated_faults_do_what_they_say():
    s = le13()
    clean = simulate_faulty(s, X0, 50, [], rng=3)
    bias = simulate_faulty(s, X0, 50, [Fault("sensor_bias", start=20, output=1, magnitude=0.7)], rng=3)
    np.testing.assert_array_equal(bias.x, clean.x)
    np.testing.assert_allclose(bias.y[20:, 1] - clean.y[20:, 1], 0.7)
    np.testing.assert_array_equal(bias.y[:20], clean.y[:20])
    stuck = simulate_faulty(s, X0, 50, [Fault("stuck_sensor", start=20, output=0)], rng=3)
    assert np.all(stuck.y[20:, 0] == clean.y[19, 0])
    frozen = simulate_faulty(s, X0, 50, [Fault("stuck_sensor", start=20, output=0, magnitude=4.0, value_given=True)],
                             rng=3)
    assert np.all(frozen.y[20:, 0] == 4.0)
    dA = np.array([[0.0, 0.0], [0.0, 0.2]])
    changed = simulate_faulty(s, X0, 50, [Fault("parameter_change", start=30, delta_A=dA)], rng=3)
    np.testing.assert_array_equal(changed.x[:31], clean.x[:31])
    np.testing.assert_allclose(changed.x[31], (s.A + dA) @ changed.x[30] + s.E @ changed.omega[30])
    p = with_input()
    u = np.ones((40, 1))
    ok = simulate_faulty(p, Zonotope([0, 0], np.eye(2)), 40, [], rng=5, u=u)
    lost = simulate_faulty(p, Zonotope([0, 0], np.eye(2)), 40, [Fault("actuator_loss", start=10, input=0,
                                                                        magnitude=1.0)], rng=5, u=u)
    np.testing.assert_array_equal(lost.x[:11], ok.x[:11])
    np.testing.assert_allclose(lost.x[11], p.A @ lost.x[10] + p.E @ lost.omega[10])  # no actuation
    np.testing.assert_array_equal(lost.u, u)  # the commanded input is what the estimator sees


def test_bank_isolates_the_faulty_sensor():
    s = le13()
    sim = simulate_faulty(s, X0, 150, [Fault("sensor_bias", start=70, output=0, magnitude=3.0)], rng=6,
                          disturbance="vertex")
    bank = FaultBank(s, X0, [nominal(s, X0), sensor_bias(s, X0, 0, bound=4.0), sensor_bias(s, X0, 1, bound=4.0),
                             stuck_sensor(s, X0, 1)])
    iso = bank.run(sim.y)
    assert iso.rejected_at[0] is not None and iso.rejected_at[0] >= 70
    assert "sensor_bias[y0]" in iso.consistent_at_end
    assert "nominal" not in iso.consistent_at_end
    assert "sensor_bias[y1]" not in iso.consistent_at_end and "stuck_sensor[y1]" not in iso.consistent_at_end
    assert iso.consistent.shape == (150, 4)
    assert iso.consistent[:70].all()  # nothing is rejected before the fault
    assert not iso.consistent[-1, 0] and iso.consistent[-1, 1]
    assert "rejected at step" in iso.table() and "consistent" in iso.table()
    # fault-free data: every hypothesis that contains the true model stays consistent
    clean = simulate_faulty(s, X0, 150, [], rng=6, disturbance="vertex")
    assert len(bank.run(clean.y).consistent_at_end) == 4


def test_bank_isolates_actuator_loss_and_parameter_change():
    p = with_input()
    x0 = Zonotope([0, 0], np.eye(2))
    u = 3.0 * np.sign(np.sin(0.3 * np.arange(120)))[:, None]
    sim = simulate_faulty(p, x0, 120, [Fault("actuator_loss", start=40, input=0, magnitude=0.8)], rng=7, u=u)
    bank = FaultBank(p, x0, [nominal(p, x0), actuator_loss(p, x0, 0, max_loss=1.0, u_max=3.0),
                             stuck_sensor(p, x0, 0)])
    iso = bank.run(sim.y, u)
    assert iso.rejected_at[0] is not None and iso.rejected_at[0] >= 40
    assert "actuator_loss[u0]" in iso.consistent_at_end
    s = le13()
    A2 = s.A + np.array([[0.0, 0.0], [0.0, 0.25]])
    sim = simulate_faulty(s, X0, 120, [Fault("parameter_change", start=30, delta_A=A2 - s.A)], rng=8,
                          disturbance="vertex")
    iso = FaultBank(s, X0, [nominal(s, X0), parameter_change(s, X0, A2, name="A22+0.25")]).run(sim.y)
    assert iso.rejected_at[0] is not None and iso.rejected_at[0] >= 30
    # the changed model explains the data after the change, but not the start before it
    # (x0 is the state before the change): a guaranteed test rejects it only with evidence
    assert iso.rejected_at[1] is None or iso.rejected_at[1] < 30


def test_margin_plot_and_errors(tmp_path):
    s = le13()
    sim = simulate_faulty(s, X0, 80, [Fault("sensor_bias", start=40, output=1, magnitude=3.0)], rng=2)
    det = detect(SegmentMinEstimator(s, X0), sim.y)
    assert det.alarm == 40 and det.margin[40] > 0
    ax = det.plot(fault_start=40, title="bias on y1")
    ax.figure.savefig(tmp_path / "margins.png")
    assert (tmp_path / "margins.png").stat().st_size > 1000
    with pytest.raises(setbound.InvalidArgumentError, match="kind"):
        Fault("sensor_drift", start=3, output=0)
    with pytest.raises(setbound.InvalidArgumentError, match="output"):
        Fault("sensor_bias", start=3)
    with pytest.raises(setbound.InvalidArgumentError, match="magnitude"):
        Fault("actuator_loss", start=3, input=0, magnitude=1.5)
    with pytest.raises(setbound.DimensionError, match="output: 5"):
        simulate_faulty(s, X0, 10, [Fault("sensor_bias", start=3, output=5, magnitude=1.0)])
    with pytest.raises(setbound.DimensionError, match="delta_A"):
        simulate_faulty(s, X0, 10, [Fault("parameter_change", start=3, delta_A=np.eye(3))])
    with pytest.raises(setbound.InvalidArgumentError, match='on_inconsistency="flag"'):
        detect(SegmentMinEstimator(s, X0, on_inconsistency="raise"), sim.y)
    with pytest.raises(setbound.InvalidArgumentError, match="does not test its readings"):
        detect(KalmanFilter(s, [0, 0], np.eye(2)), sim.y)
    with pytest.raises(setbound.InvalidArgumentError, match="hypotheses"):
        FaultBank(s, X0, [])
    with pytest.raises(setbound.InvalidArgumentError, match="distinct"):
        FaultBank(s, X0, [nominal(s, X0), nominal(s, X0)])
    with pytest.raises(setbound.InvalidArgumentError, match="no input"):
        actuator_loss(s, X0, 0, 0.5, 1.0)
    with pytest.raises(setbound.DimensionError, match="x0"):
        nominal(s, Zonotope([0, 0, 0], np.eye(3)))


EXAMPLE = __import__("pathlib").Path(__file__).resolve().parents[2] / "examples" / "le13_sensor_fault.toml"


def test_example_job_with_an_injected_fault_reports_its_alarm_and_isolates_it(tmp_path, capsys):
    """The README's example: [[fault]] injects a sensor bias at step 120, the estimators raise
    their alarm after it (never before), the bank keeps only the faulty sensor's hypothesis."""
    import json

    from setbound import cli, config

    job = config.load(EXAMPLE)
    assert job.fault_start == 120 and job.faults[0].kind == "sensor_bias"
    assert np.all(job.y[120:, 0] != 0)  # the readings carry the bias (checked against the model below)
    assert cli.main(["run", str(EXAMPLE), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "summary.json").read_text())
    for row in summary["estimators"]:
        assert row["contains_truth"] is True  # before the fault
        assert row["alarms_before_fault"] == 0
        assert row["alarm_step"] is not None and 120 <= row["alarm_step"] <= 130
        assert f"alarm: {row['name']}: step {row['alarm_step']}" in out
    assert summary["isolation"]["consistent_at_end"] == ["sensor_bias[y0]"]
    assert "fault: sensor_bias on y0 from step 120" in out and "rejected at step" in out
    assert (tmp_path / "margins.png").stat().st_size > 10000


def test_fault_tables_are_validated_by_name(tmp_path):
    from setbound import config

    base = EXAMPLE.read_text()

    def load(text):
        p = tmp_path / "job.toml"
        p.write_text(text)
        return config.load(p)

    with pytest.raises(config.ConfigError, match=r"fault\[1\]\.output: 7 is out of range"):
        load(base + '\n[[fault]]\nkind = "stuck_sensor"\noutput = 7\nstart = 3\n')
    with pytest.raises(config.ConfigError, match=r"fault\[1\]\.kind"):
        load(base + '\n[[fault]]\nkind = "drift"\nstart = 3\n')
    with pytest.raises(config.ConfigError, match=r"fault\[1\]: input does not apply to a sensor_bias"):
        load(base + '\n[[fault]]\nkind = "sensor_bias"\noutput = 0\ninput = 0\nmagnitude = 1.0\nstart = 3\n')
    with pytest.raises(config.ConfigError, match=r"hypothesis\[4\]\.bound"):
        load(base + '\n[[hypothesis]]\nkind = "sensor_bias"\noutput = 1\nname = "b1"\n')
    with pytest.raises(config.ConfigError, match=r"hypothesis: the names must be distinct"):
        load(base + '\n[[hypothesis]]\nkind = "nominal"\n')
    with pytest.raises(config.ConfigError, match=r"fault: faults are injected into a simulated plant"):
        (tmp_path / "d.csv").write_text("y0,y1\n0,0\n")
        load(base.split("[simulation]")[0] + '[data]\nfile = "d.csv"\n[[fault]]\nkind = "sensor_bias"\noutput = 0\n'
             'start = 0\nmagnitude = 1.0\n[[estimator]]\nmethod = "segment_min"\n')
