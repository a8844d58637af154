"""`strainwave diagnose`: a recording against the simulation -> verdict, located and named physics."""
from .pipeline import Diagnosis, Verdict, diagnose, diagnose_file
from .recording import Recording, RecordingKind, parse_recording, parse_text

__all__ = ["Diagnosis", "Verdict", "Recording", "RecordingKind", "diagnose", "diagnose_file", "parse_recording", "parse_text"]
