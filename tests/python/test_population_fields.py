"""Populations coupled to diffusing fields from Python (docs/fields.md "Agents and fields"): the
coupling from dicts, writable views of the fields, read-only views of the samples at the agents
that a user rule reads, the amount deposited, and bad keys."""
import numpy as np
import pytest

from moreau import particles


def lattice(interval=10, variables=()):
    """16 agents of radius 0.3 at the centres of the unit voxels of [0, 4]², no motion."""
    rules = particles.PopulationRules(types=[particles.AgentType(name="cell", radius=0.3)],
                                      interval=interval)
    rules.variables = list(variables)
    x = np.array([[i + 0.5, j + 0.5] for j in range(4) for i in range(4)])
    return particles.Population(rules, ["cell"] * 16, x, h=0.01)


def couple(p, response, initial=1.0, **kw):
    p.couple_fields(spacing=1.0, lower=[0.0, 0.0], upper=[4.0, 4.0],
                    substrates=[{"name": "oxygen", "initial": initial}],
                    responses=[{"type": "cell", "substrate": "oxygen", **response}], **kw)


def test_uptake_in_a_well_mixed_box_follows_the_exact_discrete_solution():
    p = lattice()
    couple(p, {"uptake_rate": 2.0})
    assert p.field_names == ["oxygen"]
    U = 2.0 * np.pi * 0.09
    p.step(50)  # 5 rule steps of Δt = 0.1
    assert p.field_total("oxygen") == pytest.approx(16.0 / (1.0 + 0.1 * U) ** 5, rel=1e-13)
    assert p.field("oxygen").shape == (4, 4)
    np.testing.assert_allclose(p.field_values("oxygen"), p.field("oxygen").ravel(), rtol=1e-14)


def test_fields_are_writable_views_and_samples_read_only():
    p = lattice()
    couple(p, {"chemotaxis": 1.0}, interpolation="linear")
    c = p.field("oxygen")
    assert c.flags.writeable and np.shares_memory(c, p.field("oxygen"))
    c[:] = np.arange(4.0)[None, :] + 0.5  # c = x
    g = p.field_gradients("oxygen")
    assert g.shape == (16, 2) and not g.flags.writeable
    assert not p.field_values("oxygen").flags.writeable
    # The samples are those of the last rule step: at the coupling c = 1 everywhere; after one
    # rule step ∇c ≈ (1, 0) in the interior (the zero-flux faces flatten it a little).
    assert not p.field_gradients("oxygen").any()
    p.step(10)
    inner = (p.positions[:, 0] > 1.0) & (p.positions[:, 0] < 3.0)
    g = p.field_gradients("oxygen")[inner]
    assert np.all((g[:, 0] > 0.9) & (g[:, 0] <= 1.0)) and np.abs(g[:, 1]).max() < 1e-12


def test_a_user_rule_reads_the_samples_and_switches_secretion():
    p = lattice(variables=[particles.AgentVariable("on", 1.0)])
    couple(p, {"amount_rate": 1.0, "secretion_variable": "on"}, initial=0.0)
    seen = []

    def rule(pop, divide, die):
        seen.append(pop.field_values("oxygen").copy())
        pop.variable("on")[:] = 0.0  # every agent stops secreting from now on

    p.rule = rule
    p.step(30)
    # One rule step of Δt = 0.1 with secretion (16 agents × 1 × 0.1), then none.
    assert p.field_total("oxygen") == pytest.approx(1.6, rel=1e-13)
    assert len(seen) == 3 and seen[0].sum() > 0.0


def test_bad_keys_raise_value_errors_naming_them():
    p = lattice()
    with pytest.raises(ValueError, match="responses.uptake: unknown key"):
        couple(p, {"uptake": 1.0})
    with pytest.raises(ValueError, match="uptake_rate"):
        couple(p, {"uptake_rate": -1.0})
    with pytest.raises(ValueError, match="unknown substrate 'sugar'"):
        p.couple_fields(spacing=1.0, lower=[0.0, 0.0], upper=[4.0, 4.0],
                        substrates=[{"name": "oxygen"}],
                        responses=[{"type": "cell", "substrate": "sugar"}])
    with pytest.raises(ValueError, match="couple_fields first"):
        lattice().field("oxygen")
