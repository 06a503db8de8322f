; The Get Up & Go test (Timed Up and Go) as a planning domain for PELEA's Decision Support
; (STRIPS, positive preconditions only, so pyperplan and any classical planner read it).
;
; As in the Barthel domain, actions assume the expected outcome (the patient stays, the trial is
; timed); Monitoring records what really happened as facts: (person-absent), (trial-void) when
; a trial was abandoned (the patient left, or no timed result came), (trials-exhausted) when no
; trial is left to try; the next plan starts from there.
(define (domain get-up-and-go)
  (:requirements :strips)
  (:predicates
    (started) (person-present) (person-absent) (sit-requested)
    (unexplained) (to-seat) (ready) (go-said) (trial-timed) (trial-void)
    (trials-left) (trials-exhausted) (clinician-called)
    (result-stored) (said-goodbye))

  ; -- the person ------------------------------------------------------------------------
  (:action ask-to-sit
    :parameters ()
    :precondition (and (started) (person-absent))
    :effect (and (sit-requested)))
  (:action wait-for-person
    :parameters ()
    :precondition (and (person-absent) (sit-requested))
    :effect (and (person-present) (not (person-absent)) (not (sit-requested))))

  ; -- a trial ---------------------------------------------------------------------------
  (:action explain
    :parameters ()
    :precondition (and (started) (unexplained) (person-present))
    :effect (and (to-seat) (not (unexplained))))
  (:action repeat-trial
    :parameters ()
    :precondition (and (trial-void) (trials-left) (person-present))
    :effect (and (to-seat) (not (trial-void))))
  (:action seat-patient
    :parameters ()
    :precondition (and (to-seat) (person-present))
    :effect (and (ready) (not (to-seat))))
  (:action say-go
    :parameters ()
    :precondition (and (ready) (person-present))
    :effect (and (go-said) (not (ready))))
  (:action await-result
    :parameters ()
    :precondition (and (go-said) (person-present))
    :effect (and (trial-timed) (not (go-said))))

  ; -- closing ---------------------------------------------------------------------------
  (:action store-result
    :parameters ()
    :precondition (and (trial-timed))
    :effect (and (result-stored)))
  (:action say-goodbye
    :parameters ()
    :precondition (and (result-stored))
    :effect (and (said-goodbye)))
  (:action call-clinician
    :parameters ()
    :precondition (and (trials-exhausted))
    :effect (and (clinician-called)))
  (:action end-untimed
    :parameters ()
    :precondition (and (clinician-called))
    :effect (and (said-goodbye))))
