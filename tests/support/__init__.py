"""Helpers both test suites import by package path (easyidp_toolbox.tests.support)."""
