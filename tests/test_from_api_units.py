"""BeamPumpingUnit.from_api needs its units: API 11E geometry comes in inches, and a default
of metres made a C-320 unit 39 times too large without a word."""

import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError

C320 = dict(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98)


def test_units_are_required_and_named_with_the_accepted_values():
    with pytest.raises(MechanismError, match=r"units is required, 'in' .* or 'm'") as err:
        ms.BeamPumpingUnit.from_api(**C320)
    assert isinstance(err.value, ValueError)
    for bad in ("ft", "IN", 0.0254, ["in"]):
        with pytest.raises(MechanismError, match=r"units must be 'm' or 'in', got"):
            ms.BeamPumpingUnit.from_api(**C320, units=bad)


def test_inches_and_metres_give_the_same_unit():
    inch = ms.BeamPumpingUnit.from_api(**C320, units="in")
    metre = ms.BeamPumpingUnit.from_api(**{k: v * 0.0254 for k, v in C320.items()}, units="m")
    assert inch.crank == pytest.approx(42.01 * 0.0254, rel=1e-15)
    for name in ("crank", "pitman", "rear_arm", "front_arm", "pivot_x", "pivot_y"):
        assert getattr(metre, name) == pytest.approx(getattr(inch, name), rel=1e-12)
