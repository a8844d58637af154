"""One small error hierarchy; the CLI maps each class to an exit status."""
from __future__ import annotations


class StrainwaveError(Exception):
    """Base of every error strainwave raises on purpose."""

    exit_status = 1


class InputError(StrainwaveError, ValueError):
    """Bad user input: a parameter, a recording line, a CLI flag. Exit status 2.

    Carries the offending key (or file:line), its value and what is allowed, so
    the message can name exactly what the user has to change.
    """

    exit_status = 2

    def __init__(self, key: str, value: object, allowed: str):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"{key} = {value!r}: {allowed}")


class StageError(StrainwaveError, RuntimeError):
    """A mesher, solver or check failed inside a named stage of a study. Exit status 1."""

    exit_status = 1

    def __init__(self, stage: str, study: str, detail: str):
        self.stage = stage
        self.study = study
        self.detail = detail
        super().__init__(f"{study}: {stage} failed: {detail}")


class RangeWarning(UserWarning):
    """A value is possible but outside a seed's recommended range; the run goes on."""


class MaterialWarning(RangeWarning):
    """The material constants disagree with each other (e.g. E, nu and mu); only commands that use the
    material (closed forms, FEA) show it: a STEP export does not."""
