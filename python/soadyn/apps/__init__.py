"""The command line (`soadyn`, `python -m soadyn`: cli.py) and the demos it runs."""
