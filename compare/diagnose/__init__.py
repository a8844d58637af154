"""`strainwave diagnose`: a recording against the simulation -> verdict, located and named physics."""
from strainwave.compare.diagnose.pipeline import Diagnosis, Verdict, diagnose, diagnose_file
from strainwave.compare.diagnose.recording import Recording, RecordingKind, parse_recording, parse_text

__all__ = ["Diagnosis", "Verdict", "Recording", "RecordingKind", "diagnose", "diagnose_file", "parse_recording", "parse_text"]
