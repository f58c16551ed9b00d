"""The package's typed errors, on the ground floor so that every layer raises them."""


class ParameterError(ValueError):
    """A caller's option has a bad value (names the option and what is allowed)."""
