"""A scenario's arrays of tables ([[traffic]], [[terrain]]): each table checked to be one, with only
known keys, before its own reader looks at the values; mistakes are one line naming the table."""
from __future__ import annotations

from collections.abc import Collection, Iterator


def each_table(tables, where: str, kind: str, keys: Collection[str]) -> Iterator[tuple[str, dict]]:
    """(name for messages, table) for each [[kind]] table; ValueError on the first not a table or
    with a key not in `keys`."""
    if not isinstance(tables, list):
        raise ValueError(f"{where}: {kind} is given as [[{kind}]] tables")
    for k, table in enumerate(tables, start=1):
        name = f"{where}: [[{kind}]] {k}"
        if not isinstance(table, dict):
            raise ValueError(f"{name} must be a table")
        for key in table:
            if key not in keys:
                raise ValueError(f"{name} unknown key '{key}' (known: {', '.join(keys)})")
        yield name, table
