"""The simulated factory in MuJoCo: the arena, the belt and its feeder, the boxes, the
tables and the bimanual mobile robot (:mod:`workcell.sim.world` builds and steps
it). Deliberately empty: :mod:`workcell.sim.config` and :mod:`workcell.sim.joints` are
read by the MuJoCo-free record and audit, so importing this package loads nothing."""
