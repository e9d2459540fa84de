"""Running an ESTD: the executor, its arbitrator and the trace of a run."""
