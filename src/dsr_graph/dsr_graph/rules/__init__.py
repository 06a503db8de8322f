"""Grammar rules as data (paper, Fig. 3 and Algorithm 2): their syntax, pattern matching, the
engine that chooses which rules fire, and the runner that executes them for an agent. Pure."""
