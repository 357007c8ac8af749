"""Built-in cases: each is a YAML file of defaults plus the geometry code that builds it.

``sph example NAME`` prints the YAML of case ``NAME``; a user's case file names the case and
overrides what it needs.
"""

from . import dam_break, floating_box, ship, sloshing, still_water, wave_tank

#: name -> module with ``Geometry``, ``defaults()``, ``check(cfg)`` and ``setup(cfg)``
CASES = {
    "still_water": still_water,
    "dam_break": dam_break,
    "sloshing_rect": sloshing.Rect,
    "sloshing_u": sloshing.UTank,
    "wave_tank": wave_tank,
    "floating_box": floating_box,
    "ship_decay": ship.ShipDecay,
    "damaged_ship": ship.DamagedShip,
}
