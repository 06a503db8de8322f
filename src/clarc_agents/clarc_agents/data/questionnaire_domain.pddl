; A questionnaire test (the Barthel index, the MMSE, the Lawton scale, any test definition) as a
; planning domain for PELEA's Decision Support (STRIPS + typing, so any classical planner reads
; it; pyperplan solves it here). No item is named here: the problem lists the test's items, their
; order (next, last) and whether each has options to describe (has-options, no-options).
;
; The actions assume the expected outcome (an answer comes, the person stays). Monitoring
; records what really happened as facts: (no-answer ?i), (not-understood ?i), (unsure ?i), (failed-again ?i),
; (person-absent), (clinician-needed); the next plan starts from that state, so what follows a
; deviation is chosen by the planner. The executive maps each action here to a handler.
(define (domain questionnaire)
  (:requirements :strips :typing)
  (:types item)
  (:predicates
    (started) (person-present) (person-absent) (sit-requested)
    (greeted) (explained)
    (current ?i - item) (next ?i - item ?j - item) (last ?i - item)
    (has-options ?i - item) (no-options ?i - item)
    (pending ?i - item) (introduced ?i - item) (described ?i - item) (asked ?i - item)
    (no-answer ?i - item) (not-understood ?i - item) (retry-asked ?i - item) (failed-again ?i - item)
    (unsure ?i - item) (confirm-asked ?i - item)
    (closed ?i - item)
    (clinician-ok) (clinician-needed)
    (said-goodbye) (result-stored))

  ; -- the person ------------------------------------------------------------------------
  (:action ask-to-sit
    :parameters ()
    :precondition (and (started) (person-absent))
    :effect (and (sit-requested)))
  (:action wait-for-person
    :parameters ()
    :precondition (and (person-absent) (sit-requested))
    :effect (and (person-present) (not (person-absent)) (not (sit-requested))))

  ; -- opening ---------------------------------------------------------------------------
  (:action greet
    :parameters ()
    :precondition (and (started) (person-present))
    :effect (and (greeted)))
  (:action explain
    :parameters ()
    :precondition (and (greeted) (person-present))
    :effect (and (explained)))

  ; -- one item: introduce, describe the options (if it has any), ask, wait for the answer ---
  (:action introduce
    :parameters (?i - item)
    :precondition (and (explained) (person-present) (current ?i) (pending ?i))
    :effect (and (introduced ?i) (not (pending ?i))))
  (:action describe-options
    :parameters (?i - item)
    :precondition (and (person-present) (introduced ?i) (has-options ?i))
    :effect (and (described ?i) (not (introduced ?i))))
  (:action nothing-to-describe
    :parameters (?i - item)
    :precondition (and (introduced ?i) (no-options ?i))
    :effect (and (described ?i) (not (introduced ?i))))
  (:action ask
    :parameters (?i - item)
    :precondition (and (person-present) (described ?i))
    :effect (and (asked ?i) (not (described ?i))))
  (:action await-answer
    :parameters (?i - item)
    :precondition (and (person-present) (asked ?i))
    :effect (and (closed ?i) (not (asked ?i))))

  ; -- second try: after silence the options again (voice + all on screen); after words not
  ;    understood a repetition that offers the touch screen and skipping ----------------------
  (:action options-again
    :parameters (?i - item)
    :precondition (and (person-present) (no-answer ?i))
    :effect (and (retry-asked ?i) (not (no-answer ?i))))
  (:action clarify
    :parameters (?i - item)
    :precondition (and (person-present) (not-understood ?i))
    :effect (and (retry-asked ?i) (not (not-understood ?i))))
  (:action await-answer-again
    :parameters (?i - item)
    :precondition (and (person-present) (retry-asked ?i))
    :effect (and (closed ?i) (not (retry-asked ?i))))
  ; -- an answer heard without enough confidence: "I heard: ... Is that right?" (yes closes the
  ;    item with it; no, or nothing, is recorded by Monitoring as words not understood) ------
  (:action confirm
    :parameters (?i - item)
    :precondition (and (person-present) (unsure ?i))
    :effect (and (confirm-asked ?i) (not (unsure ?i))))
  (:action await-confirmation
    :parameters (?i - item)
    :precondition (and (person-present) (confirm-asked ?i))
    :effect (and (closed ?i) (not (confirm-asked ?i))))
  (:action skip-item
    :parameters (?i - item)
    :precondition (and (failed-again ?i))
    :effect (and (closed ?i) (not (failed-again ?i))))

  ; -- moving on ---------------------------------------------------------------------------
  (:action next-item
    :parameters (?i - item ?j - item)
    :precondition (and (current ?i) (closed ?i) (next ?i ?j) (clinician-ok))
    :effect (and (current ?j) (not (current ?i))))
  (:action call-clinician
    :parameters ()
    :precondition (and (clinician-needed))
    :effect (and (clinician-ok) (not (clinician-needed))))

  ; -- closing -----------------------------------------------------------------------------
  (:action say-goodbye
    :parameters (?i - item)
    :precondition (and (current ?i) (last ?i) (closed ?i) (clinician-ok))
    :effect (and (said-goodbye)))
  (:action store-result
    :parameters ()
    :precondition (and (said-goodbye))
    :effect (and (result-stored))))
