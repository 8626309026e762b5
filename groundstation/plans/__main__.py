"""python -m groundstation.plans [OUT_DIR]: write the example plans (default examples/plans)."""
import sys
from pathlib import Path

from .examples import write_examples

for written in write_examples(Path(sys.argv[1] if len(sys.argv) > 1 else "examples/plans")):
    print(written)
