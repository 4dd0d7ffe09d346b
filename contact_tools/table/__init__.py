"""The exact-theory table's build (:mod:`.build`, ``python -m contact_tools.table build``) and its
accuracy on held-out states (:mod:`.check`, ``python -m contact_tools.table check``); the table
itself, its lookup and data are the runtime's (:mod:`contact_core.table`)."""
