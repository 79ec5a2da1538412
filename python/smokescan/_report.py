"""Results of smokescan's analyses (diagnose, fit, calibrate) as Python objects with the fields of
their JSON reports: `report.verdict`, `report.findings[0].parameters`, or `report["verdict"]`;
`report.to_dict()` gives the report as parsed JSON."""


class Report:
    """A JSON report's object: its keys as attributes (and items); nested objects are Reports."""

    def __init__(self, fields):
        self._fields = {k: _wrap(v) for k, v in fields.items()}

    def __getattr__(self, name):
        try:
            return self.__dict__["_fields"][name]
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
        return list(self._fields) + ["to_dict", "keys"]

    def to_dict(self):
        """The report as parsed JSON: dicts, lists, numbers, strings, None (JSON's null, for NaN)."""
        return {k: _unwrap(v) for k, v in self._fields.items()}

    def __eq__(self, other):
        return isinstance(other, Report) and self.to_dict() == other.to_dict()

    def __repr__(self):
        return "Report(" + ", ".join(sorted(self._fields)) + ")"


def _wrap(v):
    if isinstance(v, dict):
        return Report(v)
    if isinstance(v, list):
        return [_wrap(x) for x in v]
    return v


def _unwrap(v):
    if isinstance(v, Report):
        return v.to_dict()
    if isinstance(v, list):
        return [_unwrap(x) for x in v]
    return v
