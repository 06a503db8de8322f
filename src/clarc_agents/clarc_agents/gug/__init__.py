"""The Get Up & Go test (Timed Up and Go): what is said, and how a trial is timed from the DSR."""
