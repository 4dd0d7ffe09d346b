"""Method ``"table"``: the exact theory tabulated (:mod:`.method`), its parametrisation
(:mod:`.grid`), lookup (:mod:`.interp`), data file (:mod:`.data`) and build (:mod:`.build`,
``python -m contact_core.table build``)."""
from .method import Table, TableDomainWarning

__all__ = ["Table", "TableDomainWarning"]
