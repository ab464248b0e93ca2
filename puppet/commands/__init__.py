"""The ``puppet`` command's sub-commands, one module each: ``register(subparsers)`` adds
it to the parser, its run function does it."""
