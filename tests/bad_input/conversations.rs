//! Rows: conversations (form a group, end it, ask which one a character is in).

use crate::{
    fixture::{Harness, Setup, MAX_CONVERSATIONS, UNKNOWN_ID},
    table::{Pick, Table},
    CAPACITY, INVALID, NOT_FOUND, NULL_ARG,
};
use crowdgaze::ffi::attention::CG_NO_TARGET;
use crowdgaze::ffi::conversations::*;
use crowdgaze::ffi::status::cg_status;
use std::ptr::{null, null_mut};

/// Makes `members` a conversation, its id written to the fixture's `out.id`.
fn converse(h: &mut Harness, members: &[u32]) -> cg_status {
    unsafe { cg_crowd_set_conversation(h.crowd, members.as_ptr(), members.len(), &mut h.out.id) }
}

/// The fixture's two characters in no conversation.
fn free_pair(h: &Harness) -> [u32; 2] {
    [h.character(2), h.character(3)]
}

/// Makes a list of members from a fixture.
type Members = fn(&Harness) -> Vec<u32>;

/// Member lists `cg_crowd_set_conversation` refuses as `CG_STATUS_INVALID_ARGUMENT`: too
/// few or too many members, a member listed twice, a member already in a conversation.
fn invalid_member_lists() -> [(&'static str, Members); 8] {
    [
        ("count 0", |_| Vec::new()),
        ("count 1", |h| vec![h.character(2)]),
        ("count 9 (more than CG_MAX_CONVERSATION_MEMBERS)", |h| {
            let [a, b] = free_pair(h);
            vec![a, b, a, b, a, b, a, b, a]
        }),
        ("count 9 of unknown ids", |_| {
            (0..9).map(|k| UNKNOWN_ID + k).collect()
        }),
        ("a member listed twice", |h| {
            vec![h.character(2), h.character(2)]
        }),
        ("a member listed twice among three", |h| {
            let [a, b] = free_pair(h);
            vec![a, b, a]
        }),
        ("a member already in a conversation", |h| {
            vec![h.character(2), h.character(0)]
        }),
        ("the members of the live conversation again", |h| {
            vec![h.character(0), h.character(1)]
        }),
    ]
}

pub(crate) fn rows_conversations(t: &mut Table) {
    let f = "cg_crowd_set_conversation";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let members = free_pair(h);
        unsafe { cg_crowd_set_conversation(null_mut(), members.as_ptr(), 2, &mut h.out.id) }
    });
    t.case(f, "(members NULL, count 2)", NULL_ARG, |h| unsafe {
        cg_crowd_set_conversation(h.crowd, null(), 2, &mut h.out.id)
    });
    t.case(f, "out_group NULL", NULL_ARG, |h| {
        let members = free_pair(h);
        unsafe { cg_crowd_set_conversation(h.crowd, members.as_ptr(), 2, null_mut()) }
    });
    t.case(f, "(members NULL, count 0)", INVALID, |h| unsafe {
        cg_crowd_set_conversation(h.crowd, null(), 0, &mut h.out.id)
    });
    t.case(f, "members misaligned", INVALID, |h| {
        let members = [h.character(2), h.character(3), 0];
        let misaligned = unsafe { members.as_ptr().cast::<u8>().add(1).cast::<u32>() };
        unsafe { cg_crowd_set_conversation(h.crowd, misaligned, 2, &mut h.out.id) }
    });
    for (what, count) in [
        ("count SIZE_MAX", usize::MAX),
        ("count × 4 overflowing", usize::MAX / 4 + 1),
    ] {
        t.case(f, what, INVALID, move |h| {
            let members = free_pair(h);
            unsafe { cg_crowd_set_conversation(h.crowd, members.as_ptr(), count, &mut h.out.id) }
        });
    }
    for (what, members) in invalid_member_lists() {
        t.case(f, what, INVALID, move |h| {
            let members = members(h);
            converse(h, &members)
        });
    }
    t.character_ids(Setup::Online, f, |h, id| {
        let first = h.character(2);
        converse(h, &[first, id])
    });
    let first_members: [(&str, cg_status, Pick); 3] = [
        ("members[0] unknown", NOT_FOUND, |_| UNKNOWN_ID),
        ("members[0] the removed character", NOT_FOUND, |h| {
            h.removed_character
        }),
        ("members[0] an object", INVALID, |h| h.object()),
    ];
    for (what, expected, first) in first_members {
        t.case(f, what, expected, move |h| {
            let members = [first(h), h.character(2), h.character(3)];
            converse(h, &members)
        });
    }
    t.case_in(
        Setup::Full,
        f,
        "max_conversations (1) reached",
        CAPACITY,
        |h| {
            let members = free_pair(h);
            converse(h, &members)
        },
    );
    t.case_in(
        Setup::Full,
        f,
        "max_conversations reached, an unknown member",
        NOT_FOUND,
        |h| {
            let members = [h.character(2), UNKNOWN_ID];
            converse(h, &members)
        },
    );

    let f = "cg_crowd_remove_conversation";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_remove_conversation(null_mut(), h.conversation)
    });
    let groups: [(&str, Pick); 6] = [
        ("unknown", |_| UNKNOWN_ID),
        ("CG_NO_TARGET as", |_| CG_NO_TARGET),
        (
            "an ended conversation's (its last but one member removed)",
            |h| h.ended_conversations[0],
        ),
        ("a removed conversation's (removing it twice)", |h| {
            h.ended_conversations[1]
        }),
        ("a free slot's", |h| h.conversation + 1),
        ("the live conversation's slot's next generation's", |h| {
            h.conversation + MAX_CONVERSATIONS
        }),
    ];
    for (what, group) in groups {
        t.case(f, format!("{what} id as group"), NOT_FOUND, move |h| {
            let group = group(h);
            unsafe { cg_crowd_remove_conversation(h.crowd, group) }
        });
    }
    t.case_in(
        Setup::Full,
        f,
        "a removed conversation's id as group, max_conversations 1",
        NOT_FOUND,
        |h| unsafe { cg_crowd_remove_conversation(h.crowd, h.ended_conversations[1]) },
    );

    let f = "cg_crowd_get_conversation";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_conversation(null(), h.character(0), &mut h.out.id)
    });
    t.case(f, "out_group NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_conversation(h.crowd, h.character(0), null_mut())
    });
    t.character_ids(Setup::Online, f, |h, id| unsafe {
        cg_crowd_get_conversation(h.crowd, id, &mut h.out.id)
    });
}
