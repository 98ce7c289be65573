"""The ring-track tests' coarse track: a coarse UIC60 section and the shortest ring that holds
the coach, so that a ring builds in seconds (the tests' cost). Fine enough for what the tests
check (a method against its reference on the same ring); the physics figures use the
scenarios' defaults (docs/track.md)."""

from __future__ import annotations

#: RingTrack's section and basis keywords: the mesh's largest triangle 4e-4 m^2, the rail
#: basis to wave number 30 rad/m, the arc step 12 mm.
COARSE_SECTION = dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12e-3)
#: The same with the ring's modes kept up to 500 Hz (the vehicle's ring tests).
COARSE = dict(COARSE_SECTION, f_max=500.0)
#: scenarios.rf_system / ff_system keywords: 40 sleepers, f_limit 300 Hz, the coarse track.
RING = dict(n_sleepers=40, f_limit=300.0, track_params=COARSE)
