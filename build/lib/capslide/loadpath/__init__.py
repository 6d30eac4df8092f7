"""The load path as generators of converged states: continuation, the cap's phases, per-step measures."""
