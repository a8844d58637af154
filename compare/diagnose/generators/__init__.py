"""Test-data generators for the diagnosis: recordings written from physics the diagnosis does not model.

They are not the product: `strainwave benchmark-diagnose`, the tests and benchmarks/ use them to score the
diagnosis on data whose answer is known. Nothing in the diagnosis imports them.
"""
