"""Results of smokescan's analyses (diagnose, fit, calibrate) as Python objects with the fields of
their JSON reports: `report.verdict`, `report.findings[0].parameters`, or `report["verdict"]`;
`report.to_dict()` gives the report as parsed JSON."""


class Report:
    """A JSON report's object: its keys as attributes (and items); nested objects are Reports."""

    __slots__ = ("_fields",)

    def __init__(self, fields):
        object.__setattr__(self, "_fields", {k: _wrap(v) for k, v in fields.items()})

    def __setattr__(self, name, value):
        raise AttributeError("a Report is read-only; to_dict() gives a copy to change")

    def __delattr__(self, name):
        raise AttributeError("a Report is read-only; to_dict() gives a copy to change")

    def __reduce__(self):  # pickle and copy: rebuilt from the parsed JSON
        return (Report, (self.to_dict(),))

    def __len__(self):
        return len(self._fields)

    def get(self, name, default=None):
        return self._fields.get(name, default)

    def items(self):
        return self._fields.items()

    def __getattr__(self, name):
        try:
            return object.__getattribute__(self, "_fields")[name]
        except KeyError:
            raise AttributeError(name) from None

    def __getitem__(self, name):
        return self._fields[name]

    def __contains__(self, name):
        return name in self._fields

    def __iter__(self):
        return iter(self._fields)

    def keys(self):
        return self._fields.keys()

    def __dir__(self):
        return list(self._fields) + ["to_dict", "keys", "items", "get"]

    def to_dict(self):
        """The report as parsed JSON: dicts, lists, numbers, strings, None (JSON's null, for NaN)."""
        return {k: _unwrap(v) for k, v in self._fields.items()}

    __hash__ = None

    def __eq__(self, other):
        return isinstance(other, Report) and self.to_dict() == other.to_dict()

    def __repr__(self):
        return "Report(" + ", ".join(sorted(self._fields)) + ")"


def _wrap(v):
    if isinstance(v, dict):
        return Report(v)
    if isinstance(v, list):  # JSON's lists as tuples: a Report is read-only all the way down
        return tuple(_wrap(x) for x in v)
    return v


def _unwrap(v):
    if isinstance(v, Report):
        return v.to_dict()
    if isinstance(v, tuple):
        return [_unwrap(x) for x in v]
    return v
