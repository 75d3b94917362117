"""Dataset exports of the record, and re-rendering from recorded states.

- :func:`workcell.export.lerobot_export.export_lerobot`: LeRobotDataset v3.0;
- :func:`workcell.export.hdf5_export.export_hdf5`: robomimic-style HDF5;
- :func:`workcell.export.rendering.render_trials`: MP4s of robot cameras;
- :func:`workcell.export.replay.replay_check`: restored states reproduce recorded poses.

Features and their conventions are defined once, in :mod:`.features` and
:mod:`.episode_data`; every episode keeps its provenance (:mod:`.provenance`). Camera
images come from the trials' recorded videos where they can be used, else from rendering
(:mod:`.camera_sources`, :mod:`.camera_images`). Nothing is
imported here, so ``import workcell.export`` stays cheap (no MuJoCo, pyarrow or h5py).
"""
