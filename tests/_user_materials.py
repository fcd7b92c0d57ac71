"""A user's own materials entry for the tests of stores and runs: a sand whose density
(``MY_SAND.format(density)``) the tests edit between or during runs."""

MY_SAND = """
[solid.my-sand]
density = {}
asperity_height = 1e-6
restitution_dry = 0.8
size_range = [2e-4, 6e-4]
source = "my lab"
confidence = "measured once"
"""
