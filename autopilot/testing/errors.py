"""The one error the plugin raises: what went wrong with the simulated vehicle, in one line."""


class FireflyError(AssertionError):
    """Fails the test (an AssertionError, so pytest reports a failure, not a crash in the plugin)."""
