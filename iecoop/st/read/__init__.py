"""The read wing of the ST bridge: Structured Text -> a Python module of iecoop classes.

``parse`` turns files and projects into blark trees with their file and line; ``translate`` turns
those trees into the module's text in two passes (the symbol table, then the classes).
"""
