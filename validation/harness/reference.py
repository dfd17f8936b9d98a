"""Reference data files: '#' provenance header lines, one CSV header row, numbers."""
import re
from pathlib import Path

import numpy as np

from .errors import HarnessError


class ReferenceFile:
    """Numeric columns are read as floats on demand; text columns (model or code
    names in tables of several codes) select rows with `rows_where`."""

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
                    rows.append([x.strip() for x in line.split(",")])
        if names is None or not rows:
            raise HarnessError(f"reference file '{rel}' has no data rows")
        if not self.header:
            raise HarnessError(f"reference file '{rel}' has no provenance header")
        self.names = names
        self.rows = rows
        self.rel = rel

    def _index(self, name):
        if name not in self.names:
            raise HarnessError(f"reference file '{self.rel}' has no column '{name}' (columns: {', '.join(self.names)})")
        return self.names.index(name)

    def column(self, name, rows=None):
        i = self._index(name)
        try:
            return np.array([float(self.rows[r][i]) for r in (range(len(self.rows)) if rows is None else rows)])
        except ValueError:
            raise HarnessError(f"reference file '{self.rel}': column '{name}' is not numeric") from None

    def rows_where(self, where):
        """Indices of the rows whose columns equal the given values (text or number)."""
        idx = {k: self._index(k) for k in where}
        out = []
        for r, row in enumerate(self.rows):
            ok = True
            for k, v in where.items():
                cell = row[idx[k]]
                if isinstance(v, (int, float)):
                    try:
                        ok = ok and float(cell) == float(v)
                    except ValueError:
                        ok = False
                else:
                    ok = ok and cell == str(v)
            if ok:
                out.append(r)
        if not out:
            raise HarnessError(f"reference file '{self.rel}': no row where {where}")
        return out

    def header_value(self, pattern):
        for line in self.header:
            m = re.search(pattern, line)
            if m:
                return float(m.group(1))
        raise HarnessError(f"reference file '{self.rel}': no header line matches {pattern!r}")

    def citation(self):
        return self.header[0] if self.header else ""
