"""Ranges from ArduPilot's parameter documentation comments, as full parameter names.

ArduPilot documents each parameter next to its definition with `// @Param: NAME` followed by
`// @Field: value` lines; `// @Group: PREFIX` with `// @Path: file[,file]` says that the parameters
documented in those files (relative to the documenting file's folder) are named PREFIX + their own
name. The vehicle's Parameters.cpp is the root. Fields tagged for other vehicles (`@Range{Plane}`)
are skipped; a parameter tagged only for other vehicles is not Copter's.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

VEHICLE = "Copter"
_FIELD = re.compile(r"^\s*//\s*@(\w+)(?:\{([^}]*)\})?:\s?(.*?)\s*$")


@dataclass
class DocParam:
    name: str
    fields: dict  # field name -> text, Copter's own tagged value taking precedence

    def range(self) -> tuple[float, float] | None:
        text = self.fields.get("Range")
        if text is None:
            return None
        words = text.split()
        try:
            low, high = float(words[0]), float(words[1])
        except (IndexError, ValueError):
            return None
        return (low, high) if low <= high else None


def _for_copter(tags: str | None) -> bool:
    return tags is None or VEHICLE in {t.strip() for t in tags.split(",")}


def _blocks(text: str):
    """(kind, name, fields, paths) for each @Param and @Group documented in a source file."""
    current = None
    for line in text.splitlines():
        match = _FIELD.match(line)
        if match is None:
            if current is not None and not line.strip().startswith("//"):
                yield current
                current = None
            continue
        field, tags, value = match.groups()
        if field in ("Param", "Group"):
            if current is not None:
                yield current
            current = {"kind": field, "name": value.split()[0] if value.split() else "",
                       "for_copter": _for_copter(tags), "fields": {}, "tagged": set(), "paths": []}
        elif current is None:
            continue
        elif field == "Path":
            current["paths"].extend(p.strip() for p in value.split(",") if p.strip())
        elif _for_copter(tags):
            # Copter's own tagged value wins over the untagged one, whatever their order.
            if tags is not None or field not in current["tagged"]:
                current["fields"][field] = value
            if tags is not None:
                current["tagged"].add(field)
    if current is not None:
        yield current


def documented_params(vehicle_dir: Path) -> dict[str, DocParam]:
    """Every parameter documented for the vehicle in vehicle_dir (e.g. ArduCopter), by full name."""
    found: dict[str, DocParam] = {}
    visited: set[tuple[Path, str]] = set()

    def walk(path: Path, prefix: str) -> None:
        key = (path.resolve(), prefix)
        if key in visited or not path.is_file():
            return
        visited.add(key)
        for block in _blocks(path.read_text(errors="replace")):
            if block["kind"] == "Param" and block["for_copter"]:
                names = [prefix + block["name"]]
                if "Vector3Parameter" in block["fields"]:
                    names = [names[0] + axis for axis in ("_X", "_Y", "_Z")]
                for name in names:
                    found.setdefault(name, DocParam(name, block["fields"]))
            elif block["kind"] == "Group":
                for sub in block["paths"]:
                    walk(path.parent / sub, prefix + block["name"])

    walk(vehicle_dir / "Parameters.cpp", "")
    return found
