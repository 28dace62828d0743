"""The end-to-end cases of aries by topic (run by ctest/e2e.py). Each topic module registers its cases in CASES (case
name -> function of no arguments); common.py holds the command line (ARGS) and the helpers shared by topics."""
