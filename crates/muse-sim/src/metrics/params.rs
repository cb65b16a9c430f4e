//! The flight-model parameters and booking lead as a summary records them: the one record of
//! parameters in user units, [`muse_formats::params::ParamsRecord`], with the booking lead of
//! generated demand.

use muse_formats::params::BookingLeadRecord;

use crate::demand::BookingLead;

impl From<BookingLead> for BookingLeadRecord {
    fn from(lead: BookingLead) -> Self {
        BookingLeadRecord {
            from: lead.min.as_secs_f64() / 60.0,
            to: lead.max.as_secs_f64() / 60.0,
        }
    }
}
