"""What one Dask task runs: one trial of the simulation, through the lieservo.sim module."""
from __future__ import annotations


def run_trial(case: str, seed: int, observations: str, draws: dict) -> dict:
    """lieservo.sim.push_trial's result for the trial (case, seed) with the spec's draws. Imported on
    the worker, so that a worker needs only lieservo.sim on its path, not the client's state."""
    from lieservo import sim
    return sim.push_trial(case, seed, observations=observations, **draws)
