"""The two errors of a campaign: a spec that cannot run, and a campaign that cannot go on."""
from __future__ import annotations


class SpecError(ValueError):
    """A campaign spec refused before any run: the message names the file and lists every problem
    found, each naming its item; `problems` holds those problems one by one."""

    def __init__(self, message: str, problems=None):
        super().__init__(message)
        self.problems = tuple(problems) if problems else (message,)


class CampaignError(RuntimeError):
    """A campaign that cannot start or go on for a reason outside the spec: a results directory
    holding another spec, workers without soadyn, a scheduler that cannot be reached."""


class ResultsDirectoryError(CampaignError):
    """A results directory that cannot take this campaign: another spec's results, or not a campaign's."""
