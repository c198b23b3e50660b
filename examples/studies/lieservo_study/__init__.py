"""lieservo studies: pass rates with Wilson intervals from thousands of simulated pushing trials,
run on Dask (docs/studies.md). The command line is examples/studies/study.py."""
