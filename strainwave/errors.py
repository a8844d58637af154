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
        super().__init__(f"{_clip(str(key))} = {_clip(_repr(value))}: {_clip(allowed, ALLOWED_CHARS)}")


# An error is one terminal line: a 10 MB string value must not become a 10-million-character line, so
# the echoed key and value are cut to what a reader can still compare with the file (the full value
# stays on the exception). The explanation may be longer (it lists allowed keys) but is bounded too.
ECHO_CHARS = 120
ALLOWED_CHARS = 2000


def _repr(value: object) -> str:
    """repr() that cannot fail: Python refuses to print integers of more than 4300 digits, and a table
    nested 5,000 levels deep exhausts the recursion limit; containers are shown a few levels deep."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 1000:
        return f"an integer of about {int(value.bit_length() * 0.30103)} digits"
    if isinstance(value, (dict, list, tuple, set, frozenset)):
        import reprlib
        shown = reprlib.Repr()
        shown.maxlevel, shown.maxdict, shown.maxlist, shown.maxtuple, shown.maxset = 3, 6, 6, 6, 6
        shown.maxstring = shown.maxother = ECHO_CHARS
        try:
            return shown.repr(value)
        except (RecursionError, ValueError):
            return "a value nested too deeply to show"
    return repr(value)


def _clip(text: str, limit: int = ECHO_CHARS) -> str:
    from strainwave.input_guard import printable   # a file's control codes must not reach the terminal raw
    text = printable(text.replace("\n", " ").replace("\r", " "))
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


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
