"""The one exception type of the harness: a message that names file, key and expectation."""


class HarnessError(Exception):
    pass
