"""One module per ``linkstress`` subcommand, each with ``register(subparsers)``."""
