"""A motion's named tracks: a missing name is a MechanismError that lists the known names (and
still a KeyError), for every way a Motion is built."""

import pickle

import pytest

import mechsynth as ms
from mechsynth import UnknownNameError
from mechsynth.errors import MechanismError
from mechsynth.kinematics.tracks import Tracks


def _motions():
    phi = ms.cycle(36)
    return {
        "linkage": ms.six_link().motion(phi, speed=ms.rpm(60)),  # Motion(...)
        "four-bar": ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2).motion(phi),
        "slider-crank": ms.SliderCrank(crank=0.1, rod=0.4).motion(phi, speed=10.0),
    }


@pytest.mark.parametrize("kind", ["linkage", "four-bar", "slider-crank"])
def test_a_missing_name_says_what_there_is(kind):
    m = _motions()[kind]
    for tracks, what in ((m.points, "point"), (m.links, "link"), (m.sliders, "slider")):
        assert isinstance(tracks, Tracks) and isinstance(tracks, dict)
        known = ", ".join(sorted(tracks)) or "none"
        with pytest.raises(UnknownNameError) as err:
            tracks["nope"]
        assert str(err.value) == f"no {what} 'nope' in this motion; its {what}s: {known}"
        assert isinstance(err.value, MechanismError) and isinstance(err.value, KeyError)
        assert tracks.get("nope") is None and "nope" not in tracks


def test_the_old_ways_keep_working_and_a_near_name_is_suggested():
    m = _motions()["linkage"]
    try:
        m.links["nope"]
    except KeyError as e:  # code written against a plain dict
        assert "its links: AB, DB, KN, N, OA" in str(e)
    with pytest.raises(ValueError, match=r"no point 'n' in this motion \(did you mean 'N'\?\)"):
        m.points["n"]
    with pytest.raises(MechanismError, match=r"did you mean 'DB'\?"):
        m.links["DBB"]
    assert m.links["DB"] is dict(m.links)["DB"]
    back = pickle.loads(pickle.dumps(m))
    assert type(back.links) is type(m.links) and list(back.links) == list(m.links)
    with pytest.raises(UnknownNameError):
        back.links["nope"]


def test_a_machine_motion_built_with_plain_dicts():
    m = ms.NailHeader().motion(ms.cycle(12))  # Motion(...) with dict literals
    assert set(m.links) == {"crank", "rod", "ejector"}
    with pytest.raises(UnknownNameError, match="no link 'nope' .* its links: crank, ejector, rod"):
        m.links["nope"]
