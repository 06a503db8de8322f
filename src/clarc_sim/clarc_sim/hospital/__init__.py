"""The CGAmed hospital-server stand-in: the clinician's Start, the results store, notifications
and the clinician's dashboard."""
