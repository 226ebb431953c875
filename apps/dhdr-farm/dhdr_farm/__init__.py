"""dhdr-farm: runs a dhdr pipeline over a frame range as Slurm job arrays or local processes.

The package is split by concept: pipeline (the JSON file), frames (patterns and chunks),
plan (jobs, their tasks and dependencies), script (the batch script every task runs),
slurm and local (the two engines), status, and cli. Standard library only.
"""

VERSION = "0.1.0"
