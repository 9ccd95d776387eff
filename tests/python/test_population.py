"""moreau.particles.Population from Python: views without copies, a user drift against its exact
displacement, a user rule's marks and variables, errors from user code, the observer and Ctrl-C."""
import signal

import numpy as np
import pytest

from moreau import particles


def line(n=3, interval=1000, variables=(), **type_keys):
    """n agents of one type 2 apart on the x axis (no contacts), h = 0.01, no noise."""
    rules = particles.PopulationRules(types=[particles.AgentType(name="cell", **type_keys)],
                                      interval=interval)
    rules.variables = list(variables)
    x = np.stack([2.0 * np.arange(n), np.zeros(n)], axis=1)
    return particles.Population(rules, ["cell"] * n, x, h=0.01)


def test_views_share_the_populations_memory():
    p = line(variables=[particles.AgentVariable("food", 2.0)])
    assert np.shares_memory(p.radii, p.radii)  # the same storage on every access
    # Fields of one array of agents: strided views a fixed offset apart.
    address = lambda a: a.__array_interface__["data"][0]  # noqa: E731
    assert p.ids.strides == p.radii.strides and 0 < address(p.radii) - address(p.ids) < 64
    p.radii[1] = 0.25
    assert p.radii[1] == 0.25
    food = p.variable("food")
    food[2] = 5.0
    assert p.variable("food")[2] == 5.0
    assert not p.ids.flags.writeable and not p.positions.flags.writeable
    assert list(p.ids) == [0, 1, 2]
    assert p.positions.shape == (3, 2) and p.polarities.shape == (3, 2)
    with pytest.raises(ValueError, match="unknown variable 'oxygen'"):
        p.variable("oxygen")


def test_a_constant_drift_moves_each_agent_by_its_exact_displacement():
    p = line()
    p.drift = lambda pop, v: v.__setitem__((slice(None), 1), 0.5 * np.arange(pop.count))
    p.step(40)
    y = np.zeros(3)
    for _ in range(40):
        y = y + 0.01 * (0.5 * np.arange(3))
    assert np.array_equal(p.positions[:, 1], y)
    assert np.array_equal(p.positions[:, 0], [0.0, 2.0, 4.0])


def test_a_rule_marks_divisions_and_deaths_and_split_amounts_are_conserved():
    p = line(n=4, interval=5, radius=0.4,
             variables=[particles.AgentVariable("amount", 8.0, "split")])
    seen = []

    def rule(pop, divide, die):
        seen.append(pop.step_count)
        if len(seen) == 1:
            divide[:2] = True
            die[3] = True

    assert p.rule is None and p.drift is None
    p.rule = rule
    assert p.rule is rule  # the user code reads back as set
    p.step(10)
    assert seen == [5, 10]
    assert p.count == 5
    assert list(p.variable("amount")) == [4.0, 4.0, 4.0, 4.0, 8.0]
    s = p.summary()
    assert (s.births, s.deaths) == (2, 1)
    assert list(p.generations) == [1, 1, 1, 1, 0]


def test_errors_in_user_code_reach_python_with_the_last_good_state():
    p = line()
    p.step(2)
    before = p.positions.copy()
    p.drift = lambda pop, v: 1 / 0
    with pytest.raises(ZeroDivisionError):
        p.step()
    assert np.array_equal(p.positions, before)
    p.drift = None
    assert p.drift is None
    p.rule = lambda pop, divide, die: pop.radii.__setitem__(0, -1.0)
    p.step(997)  # up to the rule step
    with pytest.raises(ValueError, match="radius -1"):
        p.step()


def test_a_non_finite_drift_stops_the_run_naming_the_agent():
    p = line()
    p.drift = lambda pop, v: v.__setitem__((1, 0), np.nan)
    s = p.step()
    assert s.termination == "non_finite" and "agent 1" in s.message


def test_the_observer_stops_a_run_and_ctrl_c_interrupts_between_steps():
    p = line(interval=10, growth_rate=0.01)
    steps = []

    def observer(pop):
        steps.append(pop.step_count)
        return pop.step_count < 30

    s = p.run(1.0, observer)
    assert steps == [0, 10, 20, 30] and s.termination == "interrupted"

    def interrupt(pop, v):
        if pop.step_count == 37:
            signal.raise_signal(signal.SIGINT)

    fresh = line(interval=10)
    fresh.drift = interrupt
    with pytest.raises(KeyboardInterrupt):
        fresh.run(1.0)
    assert fresh.step_count == 37  # the step whose drift raised was not taken


def test_ctrl_c_in_a_rule_leaves_its_rule_step_to_the_next_step():
    """KeyboardInterrupt inside the rule: the engine step was taken, its rule step is done first
    by the next step (the rule called again at the same step count), as if never stopped."""
    seen = []

    def rule(pop, divide, die):
        seen.append(pop.step_count)
        if len(seen) == 1:
            signal.raise_signal(signal.SIGINT)

    stopped, smooth = line(interval=10, growth_rate=0.1), line(interval=10, growth_rate=0.1)
    stopped.rule = rule
    with pytest.raises(KeyboardInterrupt):
        stopped.run(1.0)
    assert stopped.step_count == 10 and stopped.summary().rule_steps == 0
    stopped.step(10)
    smooth.step(20)
    assert seen == [10, 10, 20] and stopped.step_count == 20
    assert np.array_equal(stopped.radii, smooth.radii) and smooth.radii[0] == pytest.approx(0.52)


def test_positions_read_in_a_drift_are_gathered_once_per_step():
    """pop.positions inside a drift: one gather per step, shared by every read of that step."""
    p = line()
    reads = []
    p.drift = lambda pop, v: reads.append((pop.positions, pop.positions))
    p.step(2)
    (a, b), (c, _) = reads
    assert np.shares_memory(a, b) and np.array_equal(p.positions[:, 0], [0.0, 2.0, 4.0])
    assert not a.flags.writeable and not c.flags.writeable


def test_the_velocity_is_zero_on_entry_after_writes_errors_and_divisions():
    p = line(n=2, interval=3, radius=0.4)
    p.rule = lambda pop, divide, die: divide.__setitem__(0, pop.step_count == 3)
    entries, raised = [], []

    def drift(pop, v):
        entries.append((v.shape, bool((v == 0.0).all())))
        v[:] = 1.0
        if pop.step_count == 4 and not raised:
            raised.append(True)
            raise RuntimeError("once")

    p.drift = drift
    p.step(4)
    with pytest.raises(RuntimeError):
        p.step()
    p.step(2)
    assert [shape for shape, _ in entries] == [(2, 2)] * 3 + [(3, 2)] * 4
    assert all(zero for _, zero in entries)


def test_types_by_name_and_bad_names():
    rules = particles.PopulationRules(types=[particles.AgentType(name="a"),
                                             particles.AgentType(name="b", radius=0.3)])
    p = particles.Population(rules, ["b", 0], [[0.0, 0.0], [2.0, 0.0]])
    assert list(p.types) == [1, 0] and list(p.radii) == [0.3, 0.5]
    with pytest.raises(ValueError, match="unknown type 'c'"):
        particles.Population(rules, ["c"], [[0.0, 0.0]])


def test_an_extinct_population_has_empty_views():
    p = line(n=2, interval=1)
    p.rule = lambda pop, divide, die: die.__setitem__(slice(None), True)
    s = p.step(3)
    assert p.count == 0 and s.deaths == 2 and "no agents left" in s.message
    assert p.positions.shape == (0, 2) and p.ids.shape == (0,) and p.observe()["count"] == 0


def test_adhesion_per_pair_of_types_pulls_with_its_stiffness():
    """Two touching-range agents of types (a, b), gap g: one step moves each by h k_ab g (1 − g/ℓ)
    (forces.h); pairs the rules do not name take the uniform stiffness."""
    types = [particles.AgentType(name=n) for n in ("dark", "light")]
    rules = particles.PopulationRules(types=types, interval=1000,
                                      adhesion={("dark", "dark"): 4.0, ("light", "dark"): 1.5})
    assert rules.adhesion == {("dark", "dark"): 4.0, ("light", "dark"): 1.5}
    forces = particles.Forces(attraction=particles.PairAttraction(stiffness=0.5, range=0.3))
    g = 0.1
    for pair, k in ((("dark", "dark"), 4.0), (("dark", "light"), 1.5), (("light", "light"), 0.5)):
        p = particles.Population(rules, list(pair), np.array([[0.0, 0.0], [1.0 + g, 0.0]]),
                                 forces=forces, h=0.01)
        p.step(1)
        assert p.positions[0, 0] == pytest.approx(0.01 * k * g * (1 - g / 0.3), rel=1e-13)
        assert p.observe()["segregation"] == 0.0  # apart by g > 0.05: not touching
    rules.adhesion = {("dark", "grey"): 1.0}
    with pytest.raises(ValueError, match="adhesion.dark.grey: unknown type 'grey'"):
        rules.validate()
