"""The upsetting mechanism of the AB4115 nail-making machine (paper 003, first part), in one place.

* :mod:`.model` -- :class:`NailHeader`: crank, rod and punch-slider with the nail ejector, every
  paper parameter as a default; its motion, loads (upsetting force, ejector spring, gravity) and
  force model (joint reactions of Table 1).
* :mod:`.drive` -- the machine reduced to its crank in its clockwise crank angle, an induction
  motor through a gear, the steady speed fluctuation at 600 rpm and the flywheel.

``ms.NailHeader`` is its public name; the study is ``mechsynth study run nail-header``.
"""

from ...synthesis.design_file import register_design
from .drive import MOTOR_ASSUMPTION, nail_header_speed_fluctuation
from .model import NailHeader

__all__ = ["NailHeader", "MOTOR_ASSUMPTION", "nail_header_speed_fluctuation"]

register_design("nail-header", NailHeader)
