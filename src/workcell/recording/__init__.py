"""Recording a running session into the record: the recorder, frame capture at the sample
instant, the frame ring and the writer process, and camera media. Depends on
:mod:`workcell.record` (the store, MuJoCo-free), never the other way round."""
