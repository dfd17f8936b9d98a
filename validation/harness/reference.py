"""Reference data files: '#' provenance header lines, one CSV header row, numbers."""
import re
from pathlib import Path

import numpy as np

from .errors import HarnessError


class ReferenceFile:
    def __init__(self, root, rel):
        self.path = Path(root) / rel
        if not self.path.exists():
            raise HarnessError(f"reference file '{rel}' does not exist under {root}")
        self.header, rows, names = [], [], None
        for line in self.path.read_text().splitlines():
            if line.startswith("#"):
                self.header.append(line[1:].strip())
            elif line.strip():
                if names is None:
                    names = [n.strip() for n in line.split(",")]
                else:
                    rows.append([float(x) for x in line.split(",")])
        if names is None or not rows:
            raise HarnessError(f"reference file '{rel}' has no data rows")
        if not self.header:
            raise HarnessError(f"reference file '{rel}' has no provenance header")
        self.names = names
        self.data = np.array(rows)
        self.rel = rel

    def column(self, name):
        if name not in self.names:
            raise HarnessError(f"reference file '{self.rel}' has no column '{name}' (columns: {', '.join(self.names)})")
        return self.data[:, self.names.index(name)]

    def header_value(self, pattern):
        for line in self.header:
            m = re.search(pattern, line)
            if m:
                return float(m.group(1))
        raise HarnessError(f"reference file '{self.rel}': no header line matches {pattern!r}")

    def citation(self):
        return self.header[0] if self.header else ""
