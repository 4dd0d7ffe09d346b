"""Method ``"table"``: the exact theory tabulated (:mod:`.method`), its parametrisation
(:mod:`.grid`), lookup (:mod:`.interp`) and data file (:mod:`.data`); its build is tooling
(``python -m contact_tools.table build``, :mod:`contact_tools.table.build`)."""
from .method import Table, TableDomainWarning

__all__ = ["Table", "TableDomainWarning"]
