"""Subcommands of the `warpoptics` command line (see warpoptics/cli.py)."""
