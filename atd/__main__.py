"""`python -m atd` runs the command line."""

from atd.cli import main

main()
