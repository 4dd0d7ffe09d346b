"""Reference wheelset models (pythonfmu FMUs) coupled to the contact FMU, and their master.

See README.md in this folder.
"""
